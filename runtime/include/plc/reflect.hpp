// Field reflection for FBs and programs: one declaration next to the fields.
//
//   struct TON {
//     BOOL IN{}; TIME PT{}; BOOL Q{}; TIME ET{};
//     PLC_REFLECT(IN, PT, Q, ET)
//   };
//
// PLC_REFLECT defines `template <class V> void reflect(V& v)` that calls
// v("IN", IN), v("PT", PT), ... in declaration order. Visitors (the variable
// registry, device binding, tests) recurse into nested FBs and std::arrays.
// Up to 128 fields per declaration (internal state included: the debugger
// shows it and recordings snapshot it).
#pragma once

#include <array>
#include <type_traits>

#define PLC_RF_EXPAND(x) x
#define PLC_RF_CAT(a, b) PLC_RF_CAT_I(a, b)
#define PLC_RF_CAT_I(a, b) a##b
// clang-format off
#define PLC_RF_NARG(...) PLC_RF_EXPAND(PLC_RF_ARG_N(__VA_ARGS__, PLC_RF_RSEQ()))
#define PLC_RF_ARG_N(...) PLC_RF_EXPAND(PLC_RF_ARG_N_I(__VA_ARGS__))
#define PLC_RF_ARG_N_I(_1, _2, _3, _4, _5, _6, _7, _8, _9, _10, _11, _12, _13, _14, _15, _16, _17, _18, _19, _20, _21, _22, _23, _24, _25, _26, _27, _28, _29, _30, _31, _32, _33, _34, _35, _36, _37, _38, _39, _40, _41, _42, _43, _44, _45, _46, _47, _48, _49, _50, _51, _52, _53, _54, _55, _56, _57, _58, _59, _60, _61, _62, _63, _64, _65, _66, _67, _68, _69, _70, _71, _72, _73, _74, _75, _76, _77, _78, _79, _80, _81, _82, _83, _84, _85, _86, _87, _88, _89, _90, _91, _92, _93, _94, _95, _96, _97, _98, _99, _100, _101, _102, _103, _104, _105, _106, _107, _108, _109, _110, _111, _112, _113, _114, _115, _116, _117, _118, _119, _120, _121, _122, _123, _124, _125, _126, _127, _128, N, ...) N
#define PLC_RF_RSEQ() 128, 127, 126, 125, 124, 123, 122, 121, 120, 119, 118, 117, 116, 115, 114, 113, 112, 111, 110, 109, 108, 107, 106, 105, 104, 103, 102, 101, 100, 99, 98, 97, 96, 95, 94, 93, 92, 91, 90, 89, 88, 87, 86, 85, 84, 83, 82, 81, 80, 79, 78, 77, 76, 75, 74, 73, 72, 71, 70, 69, 68, 67, 66, 65, 64, 63, 62, 61, 60, 59, 58, 57, 56, 55, 54, 53, 52, 51, 50, 49, 48, 47, 46, 45, 44, 43, 42, 41, 40, 39, 38, 37, 36, 35, 34, 33, 32, 31, 30, 29, 28, 27, 26, 25, 24, 23, 22, 21, 20, 19, 18, 17, 16, 15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1

#define PLC_RF_ONE(f) v(#f, f);
#define PLC_RF_1(f) PLC_RF_ONE(f)
#define PLC_RF_2(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_1(__VA_ARGS__))
#define PLC_RF_3(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_2(__VA_ARGS__))
#define PLC_RF_4(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_3(__VA_ARGS__))
#define PLC_RF_5(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_4(__VA_ARGS__))
#define PLC_RF_6(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_5(__VA_ARGS__))
#define PLC_RF_7(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_6(__VA_ARGS__))
#define PLC_RF_8(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_7(__VA_ARGS__))
#define PLC_RF_9(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_8(__VA_ARGS__))
#define PLC_RF_10(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_9(__VA_ARGS__))
#define PLC_RF_11(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_10(__VA_ARGS__))
#define PLC_RF_12(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_11(__VA_ARGS__))
#define PLC_RF_13(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_12(__VA_ARGS__))
#define PLC_RF_14(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_13(__VA_ARGS__))
#define PLC_RF_15(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_14(__VA_ARGS__))
#define PLC_RF_16(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_15(__VA_ARGS__))
#define PLC_RF_17(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_16(__VA_ARGS__))
#define PLC_RF_18(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_17(__VA_ARGS__))
#define PLC_RF_19(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_18(__VA_ARGS__))
#define PLC_RF_20(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_19(__VA_ARGS__))
#define PLC_RF_21(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_20(__VA_ARGS__))
#define PLC_RF_22(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_21(__VA_ARGS__))
#define PLC_RF_23(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_22(__VA_ARGS__))
#define PLC_RF_24(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_23(__VA_ARGS__))
#define PLC_RF_25(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_24(__VA_ARGS__))
#define PLC_RF_26(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_25(__VA_ARGS__))
#define PLC_RF_27(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_26(__VA_ARGS__))
#define PLC_RF_28(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_27(__VA_ARGS__))
#define PLC_RF_29(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_28(__VA_ARGS__))
#define PLC_RF_30(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_29(__VA_ARGS__))
#define PLC_RF_31(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_30(__VA_ARGS__))
#define PLC_RF_32(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_31(__VA_ARGS__))
#define PLC_RF_33(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_32(__VA_ARGS__))
#define PLC_RF_34(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_33(__VA_ARGS__))
#define PLC_RF_35(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_34(__VA_ARGS__))
#define PLC_RF_36(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_35(__VA_ARGS__))
#define PLC_RF_37(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_36(__VA_ARGS__))
#define PLC_RF_38(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_37(__VA_ARGS__))
#define PLC_RF_39(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_38(__VA_ARGS__))
#define PLC_RF_40(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_39(__VA_ARGS__))
#define PLC_RF_41(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_40(__VA_ARGS__))
#define PLC_RF_42(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_41(__VA_ARGS__))
#define PLC_RF_43(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_42(__VA_ARGS__))
#define PLC_RF_44(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_43(__VA_ARGS__))
#define PLC_RF_45(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_44(__VA_ARGS__))
#define PLC_RF_46(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_45(__VA_ARGS__))
#define PLC_RF_47(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_46(__VA_ARGS__))
#define PLC_RF_48(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_47(__VA_ARGS__))
#define PLC_RF_49(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_48(__VA_ARGS__))
#define PLC_RF_50(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_49(__VA_ARGS__))
#define PLC_RF_51(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_50(__VA_ARGS__))
#define PLC_RF_52(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_51(__VA_ARGS__))
#define PLC_RF_53(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_52(__VA_ARGS__))
#define PLC_RF_54(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_53(__VA_ARGS__))
#define PLC_RF_55(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_54(__VA_ARGS__))
#define PLC_RF_56(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_55(__VA_ARGS__))
#define PLC_RF_57(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_56(__VA_ARGS__))
#define PLC_RF_58(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_57(__VA_ARGS__))
#define PLC_RF_59(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_58(__VA_ARGS__))
#define PLC_RF_60(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_59(__VA_ARGS__))
#define PLC_RF_61(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_60(__VA_ARGS__))
#define PLC_RF_62(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_61(__VA_ARGS__))
#define PLC_RF_63(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_62(__VA_ARGS__))
#define PLC_RF_64(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_63(__VA_ARGS__))
#define PLC_RF_65(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_64(__VA_ARGS__))
#define PLC_RF_66(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_65(__VA_ARGS__))
#define PLC_RF_67(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_66(__VA_ARGS__))
#define PLC_RF_68(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_67(__VA_ARGS__))
#define PLC_RF_69(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_68(__VA_ARGS__))
#define PLC_RF_70(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_69(__VA_ARGS__))
#define PLC_RF_71(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_70(__VA_ARGS__))
#define PLC_RF_72(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_71(__VA_ARGS__))
#define PLC_RF_73(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_72(__VA_ARGS__))
#define PLC_RF_74(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_73(__VA_ARGS__))
#define PLC_RF_75(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_74(__VA_ARGS__))
#define PLC_RF_76(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_75(__VA_ARGS__))
#define PLC_RF_77(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_76(__VA_ARGS__))
#define PLC_RF_78(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_77(__VA_ARGS__))
#define PLC_RF_79(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_78(__VA_ARGS__))
#define PLC_RF_80(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_79(__VA_ARGS__))
#define PLC_RF_81(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_80(__VA_ARGS__))
#define PLC_RF_82(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_81(__VA_ARGS__))
#define PLC_RF_83(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_82(__VA_ARGS__))
#define PLC_RF_84(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_83(__VA_ARGS__))
#define PLC_RF_85(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_84(__VA_ARGS__))
#define PLC_RF_86(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_85(__VA_ARGS__))
#define PLC_RF_87(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_86(__VA_ARGS__))
#define PLC_RF_88(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_87(__VA_ARGS__))
#define PLC_RF_89(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_88(__VA_ARGS__))
#define PLC_RF_90(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_89(__VA_ARGS__))
#define PLC_RF_91(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_90(__VA_ARGS__))
#define PLC_RF_92(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_91(__VA_ARGS__))
#define PLC_RF_93(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_92(__VA_ARGS__))
#define PLC_RF_94(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_93(__VA_ARGS__))
#define PLC_RF_95(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_94(__VA_ARGS__))
#define PLC_RF_96(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_95(__VA_ARGS__))
#define PLC_RF_97(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_96(__VA_ARGS__))
#define PLC_RF_98(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_97(__VA_ARGS__))
#define PLC_RF_99(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_98(__VA_ARGS__))
#define PLC_RF_100(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_99(__VA_ARGS__))
#define PLC_RF_101(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_100(__VA_ARGS__))
#define PLC_RF_102(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_101(__VA_ARGS__))
#define PLC_RF_103(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_102(__VA_ARGS__))
#define PLC_RF_104(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_103(__VA_ARGS__))
#define PLC_RF_105(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_104(__VA_ARGS__))
#define PLC_RF_106(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_105(__VA_ARGS__))
#define PLC_RF_107(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_106(__VA_ARGS__))
#define PLC_RF_108(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_107(__VA_ARGS__))
#define PLC_RF_109(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_108(__VA_ARGS__))
#define PLC_RF_110(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_109(__VA_ARGS__))
#define PLC_RF_111(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_110(__VA_ARGS__))
#define PLC_RF_112(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_111(__VA_ARGS__))
#define PLC_RF_113(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_112(__VA_ARGS__))
#define PLC_RF_114(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_113(__VA_ARGS__))
#define PLC_RF_115(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_114(__VA_ARGS__))
#define PLC_RF_116(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_115(__VA_ARGS__))
#define PLC_RF_117(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_116(__VA_ARGS__))
#define PLC_RF_118(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_117(__VA_ARGS__))
#define PLC_RF_119(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_118(__VA_ARGS__))
#define PLC_RF_120(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_119(__VA_ARGS__))
#define PLC_RF_121(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_120(__VA_ARGS__))
#define PLC_RF_122(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_121(__VA_ARGS__))
#define PLC_RF_123(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_122(__VA_ARGS__))
#define PLC_RF_124(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_123(__VA_ARGS__))
#define PLC_RF_125(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_124(__VA_ARGS__))
#define PLC_RF_126(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_125(__VA_ARGS__))
#define PLC_RF_127(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_126(__VA_ARGS__))
#define PLC_RF_128(f, ...) PLC_RF_ONE(f) PLC_RF_EXPAND(PLC_RF_127(__VA_ARGS__))

// clang-format on

#define PLC_RF_FIELDS(...) PLC_RF_EXPAND(PLC_RF_CAT(PLC_RF_, PLC_RF_NARG(__VA_ARGS__))(__VA_ARGS__))

// Declares the reflected fields of an FB or program, in order.
#define PLC_REFLECT(...)         \
  template <class PlcVisitor_>   \
  void reflect(PlcVisitor_& v) { \
    PLC_RF_FIELDS(__VA_ARGS__)   \
  }

// Same, for a class that extends a reflected base: the base's fields first.
#define PLC_REFLECT_DERIVED(Base, ...) \
  template <class PlcVisitor_>         \
  void reflect(PlcVisitor_& v) {       \
    Base::reflect(v);                  \
    PLC_RF_FIELDS(__VA_ARGS__)         \
  }

namespace plc {

template <class T, class V, class = void>
struct HasReflect : std::false_type {};
template <class T, class V>
struct HasReflect<T, V, std::void_t<decltype(std::declval<T&>().reflect(std::declval<V&>()))>>
    : std::true_type {};

template <class T>
struct IsStdArray : std::false_type {};
template <class T, std::size_t N>
struct IsStdArray<std::array<T, N>> : std::true_type {};

}  // namespace plc
