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

#include <cstdint>

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

  void operator()(const ScanContext& ctx) {
    // Channel-passivation acknowledge: hold a rising edge until a request
    // built after it (a new consecutive number) has been sent.
    if (CH_PASS_ACK && !ack_prev_) {
      ack_hold_ = true;
      ack_cn_ = FMOD.protocol().cons_nr();
    }
    ack_prev_ = CH_PASS_ACK;

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
    for (std::size_t i = 0; i < nord::kFDataBytes; ++i) FMOD.OUT_DATA[i] = o[i];

    FMOD(ctx);
    if (ack_hold_ && FMOD.protocol().cons_nr() != ack_cn_) ack_hold_ = false;

    std::uint8_t d[nord::kFDataBytes];
    for (std::size_t i = 0; i < nord::kFDataBytes; ++i) d[i] = FMOD.IN_DATA[i];
    QBAD = FMOD.QBAD;
    PASS_OUT = FMOD.PASS_OUT;
    ACK_REQ = FMOD.ACK_REQ;
    DIAG = FMOD.DIAG;
    DIAG_CODE = FMOD.DIAG_CODE;
    OSSD1_OFF = nord::get(d, nord::out::kOssd1Off);
    OSSD2_OFF = nord::get(d, nord::out::kOssd2Off);
    OSSD3_OFF = nord::get(d, nord::out::kOssd3Off);
    CLOCK1_OFF = nord::get(d, nord::out::kClock1Off);
    CLOCK2_OFF = nord::get(d, nord::out::kClock2Off);
    OSSD1_ON = !QBAD && !OSSD1_OFF;
    OSSD2_ON = !QBAD && !OSSD2_OFF;
    OSSD3_ON = !QBAD && !OSSD3_OFF;
    SI1 = nord::get(d, nord::out::kSi1);
    SI2 = nord::get(d, nord::out::kSi2);
    SOS_OK = nord::get(d, nord::out::kSosOk);
    SLS_OK = nord::get(d, nord::out::kSlsOk);
    SLS_LEVEL_ACT = static_cast<USINT>((nord::get(d, nord::out::kSlsLevel1) ? 2 : 0) |
                                       (nord::get(d, nord::out::kSlsLevel0) ? 1 : 0));
    SDI_P_OK = nord::get(d, nord::out::kSdiPOk);
    SDI_N_OK = nord::get(d, nord::out::kSdiNOk);
    SSM = nord::get(d, nord::out::kSsm);
    SSR_OK = nord::get(d, nord::out::kSsrOk);
  }

 private:
  bool ack_prev_ = false;
  bool ack_hold_ = false;
  std::uint32_t ack_cn_ = 0;
};

}  // namespace plc::safety
