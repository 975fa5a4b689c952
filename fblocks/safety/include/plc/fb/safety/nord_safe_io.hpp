// NORD_SAFE_IO: the safe I/O of a NORD SK TU4-PNS / SK CU4-PNS bus interface
// over PROFIsafe (spec nord-profisafe.md §2.3, §2.4, §8.1), built on F_MODULE.
//
// *** FOR TEST BENCHES AND SIMULATION ONLY. THIS IS NOT CERTIFIED SAFETY
// *** SOFTWARE. To be verified against IEC 61784-3-3 before any other use:
// everything listed in f_module.hpp (CRCs, control/status bits, F-parameter
// layout, host state machine).
//
// Inputs  (host -> device, the manual's "F-data In"): OSSD1 (In 0.0),
//   OSSD2 (In 3.0), OSSD3 (In 3.1), SOS (In 0.3), SLS (In 0.4) with
//   SLS_LEVEL 0-3 (In 1.1 bit 0, In 1.2 bit 1), SDI_P (In 1.4), SDI_N (In 1.5),
//   SSR (In 3.6), CH_PASS_ACK (In 3.7: acknowledge channel passivation; a
//   rising edge is held until one telegram has carried it, spec §8.2 step 9).
// Outputs (device -> host, "F-data Out"), all 0 while QBAD (fail-safe values):
//   OSSD1_OFF/OSSD2_OFF/OSSD3_OFF and CLOCK1_OFF/CLOCK2_OFF are the device's
//   INVERTED status bits (1 = switched off). Because the fail-safe value 0
//   would read as "on", the block also gives OSSDn_ON = NOT QBAD AND NOT
//   OSSDn_OFF, which is safe to use directly (spec §2.4, §8.5 item 9).
//   SI1, SI2 (Out 3.4/3.5), SOS_OK (0.3), SLS_OK (0.4), SLS_LEVEL_ACT
//   (1.1/1.2), SDI_P_OK (1.4), SDI_N_OK (1.5), SSM (1.7), SSR_OK (3.6).
// F-I/O DB signals and F-parameters are those of the nested F_MODULE `FMOD`
// (its port is the device handle); the main ones are mirrored here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "plc/fb/safety/f_module.hpp"
#include "plc/fb/safety/nord_fdata_bits.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::safety {

class NORD_SAFE_IO {
 public:
  F_MODULE<nord::kFDataBytes, nord::kFDataBytes> FMOD;

  // application outputs to the device
  BOOL OSSD1 = false, OSSD2 = false, OSSD3 = false;
  BOOL SOS = false, SLS = false;
  USINT SLS_LEVEL = 0;
  BOOL SDI_P = false, SDI_N = false, SSR = false;
  BOOL CH_PASS_ACK = false;

  // device status (0 while QBAD)
  BOOL OSSD1_OFF = false, OSSD2_OFF = false, OSSD3_OFF = false;
  BOOL CLOCK1_OFF = false, CLOCK2_OFF = false;
  BOOL OSSD1_ON = false, OSSD2_ON = false, OSSD3_ON = false;
  BOOL SI1 = false, SI2 = false;
  BOOL SOS_OK = false, SLS_OK = false;
  USINT SLS_LEVEL_ACT = 0;
  BOOL SDI_P_OK = false, SDI_N_OK = false, SSM = false, SSR_OK = false;

  // mirrored F-I/O DB outputs
  BOOL PASS_OUT = true, QBAD = true, ACK_REQ = false;
  BYTE DIAG = 0;
  UINT DIAG_CODE = 0;

  PLC_REFLECT(FMOD, OSSD1, OSSD2, OSSD3, SOS, SLS, SLS_LEVEL, SDI_P, SDI_N, SSR, CH_PASS_ACK,
              OSSD1_OFF, OSSD2_OFF, OSSD3_OFF, CLOCK1_OFF, CLOCK2_OFF, OSSD1_ON, OSSD2_ON, OSSD3_ON,
              SI1, SI2, SOS_OK, SLS_OK, SLS_LEVEL_ACT, SDI_P_OK, SDI_N_OK, SSM, SSR_OK, PASS_OUT,
              QBAD, ACK_REQ, DIAG, DIAG_CODE, ack_prev_, ack_hold_, ack_cn_)
  PLC_INTERNAL(ack_prev_, ack_hold_, ack_cn_)

  // Always inline, with FMOD's steady scan inside it (F_MODULE::operator()):
  // one call fewer per scan, in a program that has its registers saved.
  [[gnu::always_inline]] void operator()(const ScanContext& ctx) { scan<true>(ctx); }
  // operator() building the F-data In from the inputs every scan (tests
  // compare the two: FDataInCache in test_nord_functions.cpp).
  void scan_uncached(const ScanContext& ctx) { scan<false>(ctx); }

  template <bool Cached>
  [[gnu::always_inline]] void scan(const ScanContext& ctx) {
    // Channel-passivation acknowledge: hold a rising edge until a request
    // built after it (a new consecutive number) has been sent.
    if (CH_PASS_ACK && !ack_prev_) {
      ack_hold_ = true;
      ack_cn_ = FMOD.protocol().cons_nr();
    }
    ack_prev_ = CH_PASS_ACK;

    // The F-data In is a function of the ten input bytes OSSD1..CH_PASS_ACK
    // (one byte each, in a row: static_asserts below the class) and
    // ack_hold_ alone: built once per change of those bytes (two word
    // compares), not bit by bit every scan. Equal bytes are equal inputs,
    // so the kept F-data is the one the inputs give whatever wrote them.
    std::uint32_t fdata;
    if constexpr (Cached) {
      const unsigned char* in = reinterpret_cast<const unsigned char*>(this) + kInputsOffset;
      std::uint64_t k0;
      std::uint16_t k1;
      std::memcpy(&k0, in, 8);
      std::memcpy(&k1, in + 8, 2);
      // Bit 17 set in every key: the initial in_key1_ 0 matches none.
      const std::uint32_t k1x = k1 | (ack_hold_ ? 1u << 16 : 0u) | 1u << 17;
      if (k0 != in_key0_ || k1x != in_key1_) {
        fdata_in_ = build_fdata_in();
        in_key0_ = k0;
        in_key1_ = k1x;
      }
      fdata = fdata_in_;
    } else {
      fdata = build_fdata_in();
    }
    for (std::size_t i = 0; i < nord::kFDataBytes; ++i)
      FMOD.OUT_DATA[i] = static_cast<std::uint8_t>(fdata >> (8 * i));

    // FMOD(ctx) with the outputs below after each of its two ways: after
    // the steady scan the compiler knows the values it left (QBAD, PASS_OUT,
    // ACK_REQ FALSE...) instead of reloading them where the two ways join.
    if (FMOD.steady_scan(ctx)) [[likely]] {
      after_fmod();
    } else {
      FMOD.scan_general(ctx);
      after_fmod();
    }
  }

 private:
  // What scan() does after FMOD's call: the acknowledge hold, the mirrored
  // F-I/O DB outputs and the device status outputs.
  [[gnu::always_inline]] void after_fmod() {
    if (ack_hold_ && FMOD.protocol().cons_nr() != ack_cn_) ack_hold_ = false;

    QBAD = FMOD.QBAD;
    PASS_OUT = FMOD.PASS_OUT;
    ACK_REQ = FMOD.ACK_REQ;
    DIAG = FMOD.DIAG;
    DIAG_CODE = FMOD.DIAG_CODE;
    // The device status outputs are a function of IN_DATA and QBAD alone:
    // decoded once per change of those (status_key_), and written from the
    // decode every scan, so a value written between scans (debugger, HMI)
    // is overwritten as it always was.
    std::uint8_t d[nord::kFDataBytes];
    for (std::size_t i = 0; i < nord::kFDataBytes; ++i) d[i] = FMOD.IN_DATA[i];
    const std::uint64_t key =
        static_cast<std::uint64_t>(d[0]) | static_cast<std::uint64_t>(d[1]) << 8 |
        static_cast<std::uint64_t>(d[2]) << 16 | static_cast<std::uint64_t>(d[3]) << 24 |
        static_cast<std::uint64_t>(QBAD) << 32;
    if (key != status_key_) {
      status_ = decode_status(d, QBAD);
      status_key_ = key;
    }
    // The 17 outputs OSSD1_OFF..SSR_OK are declared one byte each in
    // DeviceStatus's order (static_asserts below the class), so the decode
    // is written as one copy of its bytes into this object's, not 17 byte
    // moves.
    std::memcpy(reinterpret_cast<unsigned char*>(this) + kStatusOffset, &status_,
                sizeof(DeviceStatus));
  }

 public:
  // The device status outputs, in their order, from the F-data the device
  // sent (IN_DATA) and QBAD: what every scan writes.
  struct DeviceStatus {
    BOOL ossd1_off = false, ossd2_off = false, ossd3_off = false;
    BOOL clock1_off = false, clock2_off = false;
    BOOL ossd1_on = false, ossd2_on = false, ossd3_on = false;
    BOOL si1 = false, si2 = false;
    BOOL sos_ok = false, sls_ok = false;
    USINT sls_level_act = 0;
    BOOL sdi_p_ok = false, sdi_n_ok = false, ssm = false, ssr_ok = false;

    friend bool operator==(const DeviceStatus&, const DeviceStatus&) = default;
  };
  static constexpr DeviceStatus decode_status(const std::uint8_t* d, bool qbad) {
    DeviceStatus s;
    s.ossd1_off = nord::get(d, nord::out::kOssd1Off);
    s.ossd2_off = nord::get(d, nord::out::kOssd2Off);
    s.ossd3_off = nord::get(d, nord::out::kOssd3Off);
    s.clock1_off = nord::get(d, nord::out::kClock1Off);
    s.clock2_off = nord::get(d, nord::out::kClock2Off);
    s.ossd1_on = !qbad && !s.ossd1_off;
    s.ossd2_on = !qbad && !s.ossd2_off;
    s.ossd3_on = !qbad && !s.ossd3_off;
    s.si1 = nord::get(d, nord::out::kSi1);
    s.si2 = nord::get(d, nord::out::kSi2);
    s.sos_ok = nord::get(d, nord::out::kSosOk);
    s.sls_ok = nord::get(d, nord::out::kSlsOk);
    s.sls_level_act = static_cast<USINT>((nord::get(d, nord::out::kSlsLevel1) ? 2 : 0) |
                                         (nord::get(d, nord::out::kSlsLevel0) ? 1 : 0));
    s.sdi_p_ok = nord::get(d, nord::out::kSdiPOk);
    s.sdi_n_ok = nord::get(d, nord::out::kSdiNOk);
    s.ssm = nord::get(d, nord::out::kSsm);
    s.ssr_ok = nord::get(d, nord::out::kSsrOk);
    return s;
  }

 private:
  bool ack_prev_ = false;
  bool ack_hold_ = false;
  std::uint32_t ack_cn_ = 0;
  // Cache of decode_status(): its key is IN_DATA[0..3] | QBAD << 32, and no
  // F-data and QBAD give ~0 (the first scan decodes). Not reflected: the
  // debugger cannot write either, so status_ is always the key's decode.
  std::uint64_t status_key_ = ~std::uint64_t{0};
  DeviceStatus status_{};
  // Cache of build_fdata_in() (F-data In bytes 0..3, byte i in bits 8i):
  // its key is the ten input bytes (in_key0_: OSSD1..SDI_N, in_key1_:
  // SSR, CH_PASS_ACK, ack_hold_ << 16, 1 << 17). Not reflected: only this
  // block writes them, from the inputs of the same scan.
  std::uint64_t in_key0_ = 0;
  std::uint32_t in_key1_ = 0;
  std::uint32_t fdata_in_ = 0;

  // The F-data In (host -> device) from the inputs, bit by bit.
  [[nodiscard]] std::uint32_t build_fdata_in() const {
    std::uint8_t o[nord::kFDataBytes] = {};
    nord::put(o, nord::in::kOssd1, OSSD1);
    nord::put(o, nord::in::kOssd2, OSSD2);
    nord::put(o, nord::in::kOssd3, OSSD3);
    nord::put(o, nord::in::kSos, SOS);
    nord::put(o, nord::in::kSls, SLS);
    nord::put(o, nord::in::kSlsLevel0, (SLS_LEVEL & 1u) != 0);
    nord::put(o, nord::in::kSlsLevel1, (SLS_LEVEL & 2u) != 0);
    nord::put(o, nord::in::kSdiP, SDI_P);
    nord::put(o, nord::in::kSdiN, SDI_N);
    nord::put(o, nord::in::kSsr, SSR);
    nord::put(o, nord::in::kChannelAck, CH_PASS_ACK || ack_hold_);
    std::uint32_t f = 0;
    for (std::size_t i = 0; i < nord::kFDataBytes; ++i)
      f |= static_cast<std::uint32_t>(o[i]) << (8 * i);
    return f;
  }

  static const std::size_t kStatusOffset;
  static const std::size_t kInputsOffset;
};

// Where the device status outputs begin; offsetof on a class that is not
// standard-layout (F_MODULE mixes access levels), which GCC and Clang
// compute as for any class without virtual bases.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Winvalid-offsetof"
#endif
inline constexpr std::size_t NORD_SAFE_IO::kStatusOffset = offsetof(NORD_SAFE_IO, OSSD1_OFF);
inline constexpr std::size_t NORD_SAFE_IO::kInputsOffset = offsetof(NORD_SAFE_IO, OSSD1);
// scan()'s key: the ten inputs OSSD1..CH_PASS_ACK, one byte each, in a row.
static_assert(sizeof(NORD_SAFE_IO::OSSD1) == 1 && sizeof(NORD_SAFE_IO::SLS_LEVEL) == 1 &&
              sizeof(NORD_SAFE_IO::CH_PASS_ACK) == 1);
static_assert(offsetof(NORD_SAFE_IO, OSSD2) == offsetof(NORD_SAFE_IO, OSSD1) + 1);
static_assert(offsetof(NORD_SAFE_IO, OSSD3) == offsetof(NORD_SAFE_IO, OSSD1) + 2);
static_assert(offsetof(NORD_SAFE_IO, SOS) == offsetof(NORD_SAFE_IO, OSSD1) + 3);
static_assert(offsetof(NORD_SAFE_IO, SLS) == offsetof(NORD_SAFE_IO, OSSD1) + 4);
static_assert(offsetof(NORD_SAFE_IO, SLS_LEVEL) == offsetof(NORD_SAFE_IO, OSSD1) + 5);
static_assert(offsetof(NORD_SAFE_IO, SDI_P) == offsetof(NORD_SAFE_IO, OSSD1) + 6);
static_assert(offsetof(NORD_SAFE_IO, SDI_N) == offsetof(NORD_SAFE_IO, OSSD1) + 7);
static_assert(offsetof(NORD_SAFE_IO, SSR) == offsetof(NORD_SAFE_IO, OSSD1) + 8);
static_assert(offsetof(NORD_SAFE_IO, CH_PASS_ACK) == offsetof(NORD_SAFE_IO, OSSD1) + 9);
// operator()'s copy of status_: every output in DeviceStatus's place.
static_assert(sizeof(NORD_SAFE_IO::DeviceStatus) == 17);
static_assert(offsetof(NORD_SAFE_IO, OSSD2_OFF) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, ossd2_off));
static_assert(offsetof(NORD_SAFE_IO, OSSD3_OFF) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, ossd3_off));
static_assert(offsetof(NORD_SAFE_IO, CLOCK1_OFF) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, clock1_off));
static_assert(offsetof(NORD_SAFE_IO, CLOCK2_OFF) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, clock2_off));
static_assert(offsetof(NORD_SAFE_IO, OSSD1_ON) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, ossd1_on));
static_assert(offsetof(NORD_SAFE_IO, OSSD2_ON) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, ossd2_on));
static_assert(offsetof(NORD_SAFE_IO, OSSD3_ON) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, ossd3_on));
static_assert(offsetof(NORD_SAFE_IO, SI1) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, si1));
static_assert(offsetof(NORD_SAFE_IO, SI2) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, si2));
static_assert(offsetof(NORD_SAFE_IO, SOS_OK) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, sos_ok));
static_assert(offsetof(NORD_SAFE_IO, SLS_OK) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, sls_ok));
static_assert(offsetof(NORD_SAFE_IO, SLS_LEVEL_ACT) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, sls_level_act));
static_assert(offsetof(NORD_SAFE_IO, SDI_P_OK) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, sdi_p_ok));
static_assert(offsetof(NORD_SAFE_IO, SDI_N_OK) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, sdi_n_ok));
static_assert(offsetof(NORD_SAFE_IO, SSM) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, ssm));
static_assert(offsetof(NORD_SAFE_IO, SSR_OK) - offsetof(NORD_SAFE_IO, OSSD1_OFF) ==
              offsetof(NORD_SAFE_IO::DeviceStatus, ssr_ok));
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

}  // namespace plc::safety
