// Field reflection for FBs and programs: declared once, next to the fields.
//
//   struct TON {
//     BOOL IN{}; TIME PT{}; BOOL Q{}; TIME ET{};
//     TIME start_{}; BOOL running_{};
//     PLC_REFLECT(IN, PT, Q, ET, start_, running_)
//     PLC_INTERNAL(start_, running_)
//   };
//
// PLC_REFLECT lists every field that tools may see, in the order they show
// it: the block's interface (inputs, outputs, a program's variables) and its
// internal state (the debugger shows it, trace and breakpoints read it, and
// recordings snapshot it). It defines `template <class V> void reflect(V& v)`
// that calls v("IN", IN, meta), ... (or v("IN", IN) for a visitor that takes
// two arguments). Visitors (the variable registry, tests) recurse into nested
// FBs and std::arrays. Up to 128 fields per declaration.
//
// Field attributes are declared after PLC_REFLECT, in the same class, by
// name; each is optional and names only fields that PLC_REFLECT lists (a
// static_assert says so otherwise). They reach the visitor in `meta`
// (FieldMeta). Today:
//
//   PLC_INTERNAL(f, ...)  the block's own state: a buffer index, a length, a
//       state-machine state, a slot or handle, an edge memory, anything whose
//       value only the block may choose. Readable (print, watch, trace,
//       breakpoints, recordings) but never written from outside: a debugger
//       write or force, a config `init:` and the HMI are refused, and say
//       why. Everything below an internal field is internal too (the
//       protocol object inside F_MODULE: `proto_.out_len_`), whatever its
//       own class declares.
//   PLC_WRITE_CHECK(f, check, ...)  pairs of a field and a const member
//       function `std::string check(T value) const` that the registry calls
//       with the value before every write from outside: "" lets it through,
//       anything else refuses the write with that reason. On an internal
//       field it is the one way to make it writable (the block validates, so
//       a write can never put it in a state that indexes out of bounds); on
//       an interface field it adds a range check to a field that stays
//       writable. Elementary and enum fields only. The check runs when the
//       write, force or init: is given (a force keeps its value), so it
//       must not depend on state that changes; the block stays robust to
//       any value its own code may store.
//
//   PLC_RETAIN(f, ...)  kept over a warm start (power loss, crash, plcrun
//       --warm), initial again after a cold start (IEC 61131-3 RETAIN).
//   PLC_PERSISTENT(f, ...)  kept over warm and cold starts; only plcrun
//       --reset-retain clears it (IEC PERSISTENT / TwinCAT PERSISTENT).
//       A field listed in both is PERSISTENT. The class is inherited: a
//       whole FB instance declared RETAIN keeps every field below it (the
//       CTU's CV, its edge memory, ...), whatever its class declares; only
//       below a field without a class do the inner declarations apply (a
//       batch block keeps its learned preact and totals on its own).
//       Located fields: only %M ones (the image is restored); a retained %I
//       or %Q is refused when the cell is built (inputs come from devices,
//       outputs start at their safe values).
//
// The library's rule (fblocks/): every member ending in `_` is internal, and
// so is an output the block reads back as the state it runs on
// (PR5510_BatchWeigh.State, AbsEncoderInit.Step, DriveAxis.State,
// PR5510_Device.ReadHolder). Other outputs stay writable as in CODESYS
// (Busy, Done, CV, ...): the next call overwrites them, and a block copes
// with any value there (a Busy set from outside ends in an error; it never
// indexes with a slot it does not hold). A program's variables belong to
// its author: writable, unless the program declares PLC_INTERNAL itself.
//
// Writes by the runtime itself are not "from outside": a recording's
// snapshot and goto's re-run restore internal state on purpose.
//
// The attributes are plain name lists next to PLC_REFLECT so that more of
// them fit the same shape: a new attribute is one more FieldMeta member, one more default
// in PLC_RF_ATTR_DEFAULTS and its macro. A class that extends a reflected
// base (PLC_REFLECT_DERIVED) declares the attributes of the fields it lists;
// the base's reflect() applies the base's own.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <type_traits>

#include "plc/types.hpp"

#define PLC_RF_EXPAND(x) x
#define PLC_RF_CAT(a, b) PLC_RF_CAT_I(a, b)
#define PLC_RF_CAT_I(a, b) a##b
// clang-format off
#define PLC_RF_NARG(...) PLC_RF_EXPAND(PLC_RF_ARG_N(__VA_ARGS__, PLC_RF_RSEQ()))
#define PLC_RF_ARG_N(...) PLC_RF_EXPAND(PLC_RF_ARG_N_I(__VA_ARGS__))
#define PLC_RF_ARG_N_I(_1, _2, _3, _4, _5, _6, _7, _8, _9, _10, _11, _12, _13, _14, _15, _16, _17, _18, _19, _20, _21, _22, _23, _24, _25, _26, _27, _28, _29, _30, _31, _32, _33, _34, _35, _36, _37, _38, _39, _40, _41, _42, _43, _44, _45, _46, _47, _48, _49, _50, _51, _52, _53, _54, _55, _56, _57, _58, _59, _60, _61, _62, _63, _64, _65, _66, _67, _68, _69, _70, _71, _72, _73, _74, _75, _76, _77, _78, _79, _80, _81, _82, _83, _84, _85, _86, _87, _88, _89, _90, _91, _92, _93, _94, _95, _96, _97, _98, _99, _100, _101, _102, _103, _104, _105, _106, _107, _108, _109, _110, _111, _112, _113, _114, _115, _116, _117, _118, _119, _120, _121, _122, _123, _124, _125, _126, _127, _128, N, ...) N
#define PLC_RF_RSEQ() 128, 127, 126, 125, 124, 123, 122, 121, 120, 119, 118, 117, 116, 115, 114, 113, 112, 111, 110, 109, 108, 107, 106, 105, 104, 103, 102, 101, 100, 99, 98, 97, 96, 95, 94, 93, 92, 91, 90, 89, 88, 87, 86, 85, 84, 83, 82, 81, 80, 79, 78, 77, 76, 75, 74, 73, 72, 71, 70, 69, 68, 67, 66, 65, 64, 63, 62, 61, 60, 59, 58, 57, 56, 55, 54, 53, 52, 51, 50, 49, 48, 47, 46, 45, 44, 43, 42, 41, 40, 39, 38, 37, 36, 35, 34, 33, 32, 31, 30, 29, 28, 27, 26, 25, 24, 23, 22, 21, 20, 19, 18, 17, 16, 15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1

#define PLC_RF_1(m, f) m(f)
#define PLC_RF_2(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_1(m, __VA_ARGS__))
#define PLC_RF_3(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_2(m, __VA_ARGS__))
#define PLC_RF_4(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_3(m, __VA_ARGS__))
#define PLC_RF_5(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_4(m, __VA_ARGS__))
#define PLC_RF_6(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_5(m, __VA_ARGS__))
#define PLC_RF_7(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_6(m, __VA_ARGS__))
#define PLC_RF_8(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_7(m, __VA_ARGS__))
#define PLC_RF_9(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_8(m, __VA_ARGS__))
#define PLC_RF_10(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_9(m, __VA_ARGS__))
#define PLC_RF_11(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_10(m, __VA_ARGS__))
#define PLC_RF_12(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_11(m, __VA_ARGS__))
#define PLC_RF_13(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_12(m, __VA_ARGS__))
#define PLC_RF_14(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_13(m, __VA_ARGS__))
#define PLC_RF_15(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_14(m, __VA_ARGS__))
#define PLC_RF_16(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_15(m, __VA_ARGS__))
#define PLC_RF_17(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_16(m, __VA_ARGS__))
#define PLC_RF_18(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_17(m, __VA_ARGS__))
#define PLC_RF_19(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_18(m, __VA_ARGS__))
#define PLC_RF_20(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_19(m, __VA_ARGS__))
#define PLC_RF_21(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_20(m, __VA_ARGS__))
#define PLC_RF_22(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_21(m, __VA_ARGS__))
#define PLC_RF_23(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_22(m, __VA_ARGS__))
#define PLC_RF_24(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_23(m, __VA_ARGS__))
#define PLC_RF_25(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_24(m, __VA_ARGS__))
#define PLC_RF_26(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_25(m, __VA_ARGS__))
#define PLC_RF_27(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_26(m, __VA_ARGS__))
#define PLC_RF_28(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_27(m, __VA_ARGS__))
#define PLC_RF_29(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_28(m, __VA_ARGS__))
#define PLC_RF_30(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_29(m, __VA_ARGS__))
#define PLC_RF_31(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_30(m, __VA_ARGS__))
#define PLC_RF_32(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_31(m, __VA_ARGS__))
#define PLC_RF_33(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_32(m, __VA_ARGS__))
#define PLC_RF_34(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_33(m, __VA_ARGS__))
#define PLC_RF_35(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_34(m, __VA_ARGS__))
#define PLC_RF_36(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_35(m, __VA_ARGS__))
#define PLC_RF_37(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_36(m, __VA_ARGS__))
#define PLC_RF_38(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_37(m, __VA_ARGS__))
#define PLC_RF_39(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_38(m, __VA_ARGS__))
#define PLC_RF_40(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_39(m, __VA_ARGS__))
#define PLC_RF_41(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_40(m, __VA_ARGS__))
#define PLC_RF_42(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_41(m, __VA_ARGS__))
#define PLC_RF_43(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_42(m, __VA_ARGS__))
#define PLC_RF_44(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_43(m, __VA_ARGS__))
#define PLC_RF_45(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_44(m, __VA_ARGS__))
#define PLC_RF_46(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_45(m, __VA_ARGS__))
#define PLC_RF_47(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_46(m, __VA_ARGS__))
#define PLC_RF_48(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_47(m, __VA_ARGS__))
#define PLC_RF_49(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_48(m, __VA_ARGS__))
#define PLC_RF_50(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_49(m, __VA_ARGS__))
#define PLC_RF_51(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_50(m, __VA_ARGS__))
#define PLC_RF_52(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_51(m, __VA_ARGS__))
#define PLC_RF_53(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_52(m, __VA_ARGS__))
#define PLC_RF_54(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_53(m, __VA_ARGS__))
#define PLC_RF_55(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_54(m, __VA_ARGS__))
#define PLC_RF_56(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_55(m, __VA_ARGS__))
#define PLC_RF_57(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_56(m, __VA_ARGS__))
#define PLC_RF_58(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_57(m, __VA_ARGS__))
#define PLC_RF_59(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_58(m, __VA_ARGS__))
#define PLC_RF_60(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_59(m, __VA_ARGS__))
#define PLC_RF_61(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_60(m, __VA_ARGS__))
#define PLC_RF_62(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_61(m, __VA_ARGS__))
#define PLC_RF_63(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_62(m, __VA_ARGS__))
#define PLC_RF_64(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_63(m, __VA_ARGS__))
#define PLC_RF_65(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_64(m, __VA_ARGS__))
#define PLC_RF_66(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_65(m, __VA_ARGS__))
#define PLC_RF_67(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_66(m, __VA_ARGS__))
#define PLC_RF_68(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_67(m, __VA_ARGS__))
#define PLC_RF_69(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_68(m, __VA_ARGS__))
#define PLC_RF_70(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_69(m, __VA_ARGS__))
#define PLC_RF_71(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_70(m, __VA_ARGS__))
#define PLC_RF_72(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_71(m, __VA_ARGS__))
#define PLC_RF_73(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_72(m, __VA_ARGS__))
#define PLC_RF_74(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_73(m, __VA_ARGS__))
#define PLC_RF_75(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_74(m, __VA_ARGS__))
#define PLC_RF_76(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_75(m, __VA_ARGS__))
#define PLC_RF_77(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_76(m, __VA_ARGS__))
#define PLC_RF_78(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_77(m, __VA_ARGS__))
#define PLC_RF_79(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_78(m, __VA_ARGS__))
#define PLC_RF_80(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_79(m, __VA_ARGS__))
#define PLC_RF_81(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_80(m, __VA_ARGS__))
#define PLC_RF_82(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_81(m, __VA_ARGS__))
#define PLC_RF_83(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_82(m, __VA_ARGS__))
#define PLC_RF_84(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_83(m, __VA_ARGS__))
#define PLC_RF_85(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_84(m, __VA_ARGS__))
#define PLC_RF_86(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_85(m, __VA_ARGS__))
#define PLC_RF_87(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_86(m, __VA_ARGS__))
#define PLC_RF_88(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_87(m, __VA_ARGS__))
#define PLC_RF_89(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_88(m, __VA_ARGS__))
#define PLC_RF_90(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_89(m, __VA_ARGS__))
#define PLC_RF_91(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_90(m, __VA_ARGS__))
#define PLC_RF_92(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_91(m, __VA_ARGS__))
#define PLC_RF_93(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_92(m, __VA_ARGS__))
#define PLC_RF_94(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_93(m, __VA_ARGS__))
#define PLC_RF_95(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_94(m, __VA_ARGS__))
#define PLC_RF_96(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_95(m, __VA_ARGS__))
#define PLC_RF_97(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_96(m, __VA_ARGS__))
#define PLC_RF_98(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_97(m, __VA_ARGS__))
#define PLC_RF_99(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_98(m, __VA_ARGS__))
#define PLC_RF_100(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_99(m, __VA_ARGS__))
#define PLC_RF_101(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_100(m, __VA_ARGS__))
#define PLC_RF_102(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_101(m, __VA_ARGS__))
#define PLC_RF_103(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_102(m, __VA_ARGS__))
#define PLC_RF_104(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_103(m, __VA_ARGS__))
#define PLC_RF_105(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_104(m, __VA_ARGS__))
#define PLC_RF_106(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_105(m, __VA_ARGS__))
#define PLC_RF_107(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_106(m, __VA_ARGS__))
#define PLC_RF_108(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_107(m, __VA_ARGS__))
#define PLC_RF_109(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_108(m, __VA_ARGS__))
#define PLC_RF_110(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_109(m, __VA_ARGS__))
#define PLC_RF_111(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_110(m, __VA_ARGS__))
#define PLC_RF_112(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_111(m, __VA_ARGS__))
#define PLC_RF_113(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_112(m, __VA_ARGS__))
#define PLC_RF_114(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_113(m, __VA_ARGS__))
#define PLC_RF_115(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_114(m, __VA_ARGS__))
#define PLC_RF_116(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_115(m, __VA_ARGS__))
#define PLC_RF_117(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_116(m, __VA_ARGS__))
#define PLC_RF_118(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_117(m, __VA_ARGS__))
#define PLC_RF_119(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_118(m, __VA_ARGS__))
#define PLC_RF_120(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_119(m, __VA_ARGS__))
#define PLC_RF_121(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_120(m, __VA_ARGS__))
#define PLC_RF_122(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_121(m, __VA_ARGS__))
#define PLC_RF_123(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_122(m, __VA_ARGS__))
#define PLC_RF_124(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_123(m, __VA_ARGS__))
#define PLC_RF_125(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_124(m, __VA_ARGS__))
#define PLC_RF_126(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_125(m, __VA_ARGS__))
#define PLC_RF_127(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_126(m, __VA_ARGS__))
#define PLC_RF_128(m, f, ...) m(f) PLC_RF_EXPAND(PLC_RF_127(m, __VA_ARGS__))

#define PLC_RF_P_2(m, a, b) m(a, b)
#define PLC_RF_P_4(m, a, b, ...) m(a, b) PLC_RF_EXPAND(PLC_RF_P_2(m, __VA_ARGS__))
#define PLC_RF_P_6(m, a, b, ...) m(a, b) PLC_RF_EXPAND(PLC_RF_P_4(m, __VA_ARGS__))
#define PLC_RF_P_8(m, a, b, ...) m(a, b) PLC_RF_EXPAND(PLC_RF_P_6(m, __VA_ARGS__))
#define PLC_RF_P_10(m, a, b, ...) m(a, b) PLC_RF_EXPAND(PLC_RF_P_8(m, __VA_ARGS__))
#define PLC_RF_P_12(m, a, b, ...) m(a, b) PLC_RF_EXPAND(PLC_RF_P_10(m, __VA_ARGS__))
#define PLC_RF_P_14(m, a, b, ...) m(a, b) PLC_RF_EXPAND(PLC_RF_P_12(m, __VA_ARGS__))
#define PLC_RF_P_16(m, a, b, ...) m(a, b) PLC_RF_EXPAND(PLC_RF_P_14(m, __VA_ARGS__))

// clang-format on

#define PLC_RF_FOR_EACH(m, ...) \
  PLC_RF_EXPAND(PLC_RF_CAT(PLC_RF_, PLC_RF_NARG(__VA_ARGS__))(m, __VA_ARGS__))
#define PLC_RF_FOR_PAIRS(m, ...) \
  PLC_RF_EXPAND(PLC_RF_CAT(PLC_RF_P_, PLC_RF_NARG(__VA_ARGS__))(m, __VA_ARGS__))
#define PLC_RF_NAME(f) #f,
#define PLC_RF_PAIR_NAME(f, check) #f,

#define PLC_RF_ONE(f)                                                                           \
  ::plc::reflect_field(v, #f, f,                                                                \
                       ::plc::FieldMeta{plc_internal_(#f, 0), plc_write_check_(#f, 0), this,    \
                                        plc_persistent_(#f, 0) ? ::plc::RetainClass::Persistent \
                                        : plc_retain_(#f, 0)   ? ::plc::RetainClass::Retain     \
                                                               : ::plc::RetainClass::None});

// The attributes' defaults (no attribute): the `long` overloads, which the
// attribute macros' `int` overloads win over. Declared again by every
// reflecting class, so a derived class never sees its base's attributes.
#define PLC_RF_ATTR_DEFAULTS(...)                                                    \
  [[maybe_unused]] static constexpr std::string_view plc_reflected_[] = {            \
      PLC_RF_FOR_EACH(PLC_RF_NAME, __VA_ARGS__)};                                    \
  static constexpr bool plc_internal_(std::string_view, long) { return false; }      \
  static constexpr bool plc_retain_(std::string_view, long) { return false; }        \
  static constexpr bool plc_persistent_(std::string_view, long) { return false; }    \
  [[nodiscard]] ::plc::WriteCheckFn plc_write_check_(std::string_view, long) const { \
    return nullptr;                                                                  \
  }

// Declares the reflected fields of an FB or program, in order.
// clang-format off
#define PLC_REFLECT(...)                       \
  template <class PlcVisitor_>                 \
  void reflect(PlcVisitor_& v) {               \
    PLC_RF_FOR_EACH(PLC_RF_ONE, __VA_ARGS__)   \
  }                                            \
  PLC_RF_ATTR_DEFAULTS(__VA_ARGS__)
// clang-format on

// Same, for a class that extends a reflected base: the base's fields first.
#define PLC_REFLECT_DERIVED(Base, ...)       \
  template <class PlcVisitor_>               \
  void reflect(PlcVisitor_& v) {             \
    Base::reflect(v);                        \
    PLC_RF_FOR_EACH(PLC_RF_ONE, __VA_ARGS__) \
  }                                          \
  PLC_RF_ATTR_DEFAULTS(__VA_ARGS__)

// An attribute that is a list of field names: `fn(name, 0)` says whether
// the field is listed.
#define PLC_RF_NAME_LIST_FN(fn, what, ...)                                                         \
  static constexpr bool fn(std::string_view plc_name_, int) {                                      \
    static_assert(                                                                                 \
        ::plc::detail::all_reflected({PLC_RF_FOR_EACH(PLC_RF_NAME, __VA_ARGS__)}, plc_reflected_), \
        what " names a field that this class's PLC_REFLECT does not list");                        \
    for (std::string_view n : {PLC_RF_FOR_EACH(PLC_RF_NAME, __VA_ARGS__)})                         \
      if (n == plc_name_) return true;                                                             \
    return false;                                                                                  \
  }
// The block's internal state (see the top of this file). After PLC_REFLECT.
#define PLC_INTERNAL(...) PLC_RF_NAME_LIST_FN(plc_internal_, "PLC_INTERNAL", __VA_ARGS__)
// Retain classes (IEC 61131-3 RETAIN / PERSISTENT, see the top of this
// file). After PLC_REFLECT.
#define PLC_RETAIN(...) PLC_RF_NAME_LIST_FN(plc_retain_, "PLC_RETAIN", __VA_ARGS__)
#define PLC_PERSISTENT(...) PLC_RF_NAME_LIST_FN(plc_persistent_, "PLC_PERSISTENT", __VA_ARGS__)

#define PLC_RF_CHECK_ONE(f, check)                                                      \
  if (plc_name_ == #f)                                                                  \
    return [](const void* plc_owner_, const void* plc_value_) -> std::string {          \
      using PlcField_ = std::remove_cvref_t<decltype(PlcSelf_::f)>;                     \
      static_assert(::plc::detail::checkable_v<PlcField_>,                              \
                    "PLC_WRITE_CHECK: only elementary and enum fields can be checked"); \
      return static_cast<const PlcSelf_*>(plc_owner_)                                   \
          ->check(*static_cast<const PlcField_*>(plc_value_));                          \
    };

// Write checks, as pairs: PLC_WRITE_CHECK(field, check, field2, check2).
// After PLC_REFLECT (and PLC_INTERNAL).
#define PLC_WRITE_CHECK(...)                                                                      \
  [[nodiscard]] ::plc::WriteCheckFn plc_write_check_(std::string_view plc_name_, int) const {     \
    static_assert(::plc::detail::all_reflected({PLC_RF_FOR_PAIRS(PLC_RF_PAIR_NAME, __VA_ARGS__)}, \
                                               plc_reflected_),                                   \
                  "PLC_WRITE_CHECK names a field that this class's PLC_REFLECT does not list");   \
    using PlcSelf_ = std::remove_cvref_t<decltype(*this)>;                                        \
    PLC_RF_FOR_PAIRS(PLC_RF_CHECK_ONE, __VA_ARGS__)                                               \
    return nullptr;                                                                               \
  }

namespace plc {

// Checks a value (native storage of the field's type) before a write from
// outside; `owner` is the object that has the field. "" or why not.
using WriteCheckFn = std::string (*)(const void* owner, const void* value);

// A field's write check, bound to the object that has the field.
struct WriteCheck {
  WriteCheckFn fn = nullptr;
  const void* owner = nullptr;
  explicit operator bool() const { return fn != nullptr; }
  [[nodiscard]] std::string operator()(const void* value) const { return fn(owner, value); }
};

// Whether a value survives a restart (IEC 61131-3 2.4.3.1 / 6.5.6): RETAIN
// over a warm start, PERSISTENT over a warm and a cold start (only a reset
// of the retain data clears it). None: initial value at every start.
enum class RetainClass : std::uint8_t { None, Retain, Persistent };
constexpr const char* to_string(RetainClass c) {
  return c == RetainClass::Persistent ? "persistent" : c == RetainClass::Retain ? "retain" : "";
}

// What a reflecting class declares about one field (PLC_INTERNAL,
// PLC_WRITE_CHECK, PLC_RETAIN, PLC_PERSISTENT).
struct FieldMeta {
  bool internal = false;
  WriteCheckFn check = nullptr;
  const void* owner = nullptr;
  RetainClass retain = RetainClass::None;
};

// Calls the visitor with the field's attributes when it takes them.
template <class V, class T>
void reflect_field(V& v, const char* name, T& field, const FieldMeta& meta) {
  if constexpr (std::is_invocable_v<V&, const char*, T&, const FieldMeta&>)
    v(name, field, meta);
  else
    v(name, field);
}

namespace detail {
template <std::size_t N>
constexpr bool all_reflected(std::initializer_list<std::string_view> names,
                             const std::string_view (&listed)[N]) {
  for (std::string_view n : names) {
    bool found = false;
    for (std::string_view l : listed) found = found || l == n;
    if (!found) return false;
  }
  return true;
}
template <class T>
inline constexpr bool checkable_v = is_elementary_v<T> || std::is_enum_v<T>;
}  // namespace detail

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
