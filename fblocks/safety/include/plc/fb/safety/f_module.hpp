// F_MODULE: the F-host driver block for one PROFIsafe F-module, with the
// signals of the Siemens F-I/O data block as its interface
// (softplc-anchors.md §4.4).
//
// *** FOR TEST BENCHES AND SIMULATION ONLY. THIS IS NOT CERTIFIED SAFETY
// *** SOFTWARE and must not be used to protect people or machines.
// The 3-byte CRC2 (generator, seeding, byte order) and the consecutive-number
// semantics rest on real traffic (safety_pdu.hpp, test_wire_vectors.cpp).
// To be verified against IEC 61784-3-3 (PROFIsafe) before any other use:
// CRC1 and the 4-byte CRC2 (crc.hpp), the control telegram's CRC2 order
// (taken to be the status telegram's), control/status byte bits
// (control_status_byte.hpp), F-parameter bit positions (f_parameters.hpp),
// and the host state machine (f_host_protocol.hpp).
//
// Start-up: once the device is online the block writes the 14-byte
// F-parameter block (CRC1 included) with a record write (index
// kFParamRecordIndex). A refused write sets DIAG bit kFParError and DIAG_CODE
// to the device's 57xx code; the write is retried every second. Then the
// cyclic protocol runs (FHostProtocol). Every 57xx code the device raises
// must reach the program (spec §5.5), also those without Device_Fault
// (channel passivation and report-only violations with P801 = 1): while
// cyclic the block reads the device's diagnosis record every kDiagPollEvery
// and at once when Device_Fault appears, shows the code in DIAG_CODE (also a
// code that came and went between two reads, through the device's code
// count and P842) and sets DIAG bit kDevCode while the device reports one.
// A device silent for three watchdog periods is parameterised again (it may
// have been power-cycled); that restart needs ACK_REI.
//
//   inputs : PASS_ON, ACK_NEC (default 1), ACK_REI, IPAR_EN, OUT_DATA
//   outputs: PASS_OUT, QBAD, ACK_REQ, IPAR_OK, DIAG, DIAG_CODE, IN_DATA,
//            VS_IN / VS_OUT (value status per channel bit: 1 = process
//            value valid, 0 = fail-safe value), STATE
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "plc/fb/safety/f_host_diag.hpp"
#include "plc/fb/safety/f_host_protocol.hpp"
#include "plc/fb/safety/f_parameters.hpp"
#include "plc/fb/safety/safety_pdu.hpp"
#include "plc/io/byte_order.hpp"
#include "plc/io/device_port.hpp"
#include "plc/io/record_request.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"
#include "plc/types.hpp"

namespace plc::safety {

// NIn: F-input data bytes (device -> host), NOut: F-output data bytes.
template <std::size_t NIn, std::size_t NOut>
class F_MODULE {
  static_assert(NIn >= 1 && NIn <= kMaxFData && NOut >= 1 && NOut <= kMaxFData);

 public:
  static constexpr std::size_t kInPdu = pdu_size(NIn);
  static constexpr std::size_t kOutPdu = pdu_size(NOut);

  io::DevicePort port;

  // F-parameters (spec §2.2); fixed NORD values are set in send_fparams().
  UINT F_Source_Add = 1;
  UINT F_Dest_Add = 1;
  UINT F_WD_Time = 100;  // ms
  USINT F_SIL = 2;       // code: 0 SIL1, 1 SIL2, 2 SIL3, 3 NoSIL
  UDINT F_iPar_CRC = 0;

  // F-I/O DB inputs.
  BOOL PASS_ON = false;
  BOOL ACK_NEC = true;
  BOOL ACK_REI = false;
  BOOL IPAR_EN = false;
  std::array<BYTE, NOut> OUT_DATA{};

  // F-I/O DB outputs (QBAD and PASS_OUT are 1 until the first valid exchange).
  BOOL PASS_OUT = true;
  BOOL QBAD = true;
  BOOL ACK_REQ = false;
  BOOL IPAR_OK = false;
  BYTE DIAG = 0;
  UINT DIAG_CODE = 0;  // last NORD 57xx code reported by the device
  std::array<BYTE, NIn> IN_DATA{};
  std::array<BYTE, NIn> VS_IN{};
  std::array<BYTE, NOut> VS_OUT{};
  FHostState STATE = FHostState::Param;

  PLC_REFLECT(port, F_Source_Add, F_Dest_Add, F_WD_Time, F_SIL, F_iPar_CRC, PASS_ON, ACK_NEC,
              ACK_REI, IPAR_EN, OUT_DATA, PASS_OUT, QBAD, ACK_REQ, IPAR_OK, DIAG, DIAG_CODE,
              IN_DATA, VS_IN, VS_OUT, STATE,
              // internal state: shown by the debugger, kept in recording snapshots
              proto_, block_, phase_, retry_at_, dev_fault_prev_, diag_read_wanted_,
              next_diag_read_, dev_code_, dev_code_count_, restart_after_fault_)
  PLC_INTERNAL(proto_, block_, phase_, retry_at_, dev_fault_prev_, diag_read_wanted_,
               next_diag_read_, dev_code_, dev_code_count_, restart_after_fault_)

  // Always inline (as NORD_SAFE_IO's scan around it): the caller's program
  // has its registers saved already, and the steady scan as a call paid its
  // own saves, frame and return every scan.
  [[gnu::always_inline]] void operator()(const ScanContext& ctx) {
    if (!steady_scan(ctx)) scan_general(ctx);
  }

  // The steady scan (nearly every one in Run), inline, with only what it
  // needs; false when it does not apply, having changed nothing, and
  // operator() then runs the whole block out of line in scan_general().
  // The same scan as scan_general()'s: taken only where that would take
  // the steady exchange with its phase logic doing nothing (port usable,
  // phase Cyclic, device not lost), and a steady_exchange() that returns
  // false has changed nothing (scan_general() then decides). A caller may
  // make the two calls itself (NORD_SAFE_IO: its outputs after a steady
  // scan from the steady values).
  [[gnu::always_inline]] bool steady_scan(const ScanContext& ctx) {
    if (phase_ == Phase::Cyclic && port.bound() && port.in().size() >= kInPdu &&
        port.out().size() >= kOutPdu && proto_.watchdog_expiries_in_row() < kLostAfter) [[likely]] {
      const FHostCommand cmd{PASS_ON, ACK_NEC, ACK_REI, IPAR_EN};
      if (proto_.steady_exchange<NIn, NOut>(ctx.now, port.in().first(kInPdu),
                                            port.out().first(kOutPdu), out_data(), in_data(),
                                            cmd)) {
        poll_device_diag(ctx.now);
        publish_steady();
        return true;
      }
    }
    return false;
  }

  // operator() without its inline steady path (tests compare the two).
  [[gnu::noinline]] void scan_general(const ScanContext& ctx) {
    if (!port.bound() || port.in().size() < kInPdu || port.out().size() < kOutPdu) {
      proto_.param_failed(diag::kNoLink);
      publish_passive();
      return;
    }
    // Cyclic asked first: every scan once the F-parameters are in.
    if (phase_ == Phase::Cyclic) [[likely]] {
      // The device has been silent for kLostAfter watchdog periods (e.g.
      // power-cycled, so it lost its F-parameters): send them again; the
      // restart then needs ACK_REI like any communication fault.
      if (proto_.watchdog_expiries_in_row() >= kLostAfter) {
        restart_after_fault_ = true;
        dev_code_ = 0;  // unknown until the device is back
        phase_ = Phase::SendParams;
      }
    } else {
      switch (phase_) {
        case Phase::SendParams:
          if (port.online()) send_fparams();
          break;
        case Phase::WaitParams:
          poll_fparams(ctx.now);
          break;
        case Phase::Retry:
          if (ctx.now >= retry_at_) phase_ = Phase::SendParams;
          break;
        case Phase::Cyclic:
          break;
      }
    }

    // On OUT_DATA and IN_DATA in place (out_data(), in_data()).
    FHostCommand cmd{PASS_ON, ACK_NEC, ACK_REI, IPAR_EN};
    const bool steady = proto_.cycle<true, NIn, NOut>(
        ctx.now, port.in().first(kInPdu), port.out().first(kOutPdu), out_data(), in_data(), cmd);
    if (phase_ == Phase::Cyclic) poll_device_diag(ctx.now);

    if (steady) {
      publish_steady();
      return;
    }

    STATE = proto_.state();
    PASS_OUT = proto_.pass_out();
    QBAD = proto_.qbad();
    ACK_REQ = proto_.ack_req();
    IPAR_OK = proto_.ipar_ok();
    DIAG = static_cast<BYTE>(proto_.diag() | (dev_code_ != 0 ? diag::kDevCode : 0));
    const std::uint8_t vs_in = proto_.data_valid() ? 0xFF : 0x00;
    const std::uint8_t vs_out = (STATE == FHostState::Run && !PASS_ON) ? 0xFF : 0x00;
    fill_bytes(VS_IN, vs_in);
    fill_bytes(VS_OUT, vs_out);
  }

  // The pure protocol underneath (tests and diagnostics).
  [[nodiscard]] const FHostProtocol& protocol() const { return proto_; }
  // The device's current 57xx code (P841) at the last diagnosis read, 0
  // for none (DIAG bit kDevCode).
  [[nodiscard]] std::uint16_t device_code() const { return dev_code_; }
  // The encoded F-parameter block as last sent.
  [[nodiscard]] const std::array<std::uint8_t, kFParamBlockSize>& fparam_block() const {
    return block_;
  }

 private:
  enum class Phase : std::uint8_t { SendParams, WaitParams, Retry, Cyclic };
  static constexpr std::uint32_t kLostAfter = 3;
  // How often the diagnosis record is read while cyclic. [INF] Our choice:
  // NORD codes last at least until acknowledged (q) or a power cycle (f), a
  // code that comes and goes between reads is still caught by the count.
  static constexpr TIME kDiagPollEvery = std::chrono::milliseconds(100);

  void send_fparams() {
    FParameters p;
    p.sil = F_SIL;
    // F_CRC_Length 00 = 3-byte CRC (spec §2.2); 10 = 4-byte CRC is our
    // [SPEC] reading for F-data above 12 bytes (to verify, IEC 61784-3-3).
    p.crc_length = crc2_length(NIn > NOut ? NIn : NOut) == 3 ? 0 : 2;
    p.source_add = F_Source_Add;
    p.dest_add = F_Dest_Add;
    p.wd_time_ms = F_WD_Time;
    p.ipar_crc = F_iPar_CRC;
    encode(p, block_);
    proto_.configure(p.par_crc, NOut, NIn, std::chrono::milliseconds(F_WD_Time));
    fpar_req_.reset();
    fpar_req_.prepare_write(kFParamRecordIndex, block_);
    port.submit(fpar_req_);
    phase_ = Phase::WaitParams;
  }

  void poll_fparams(TIME now) {
    const io::RecordStatus s = fpar_req_.status();
    if (s == io::RecordStatus::Done) {
      fpar_req_.reset();
      proto_.start(now, restart_after_fault_);
      restart_after_fault_ = false;
      dev_fault_prev_ = false;
      diag_read_wanted_ = true;  // learn the device's present code at once
      phase_ = Phase::Cyclic;
    } else if (s == io::RecordStatus::Error) {
      const std::uint16_t code = fpar_req_.error_code();
      const bool device_code = code >= 5700 && code <= 5799;
      if (device_code) DIAG_CODE = code;
      proto_.param_failed(device_code ? diag::kFParError : diag::kNoLink);
      fpar_req_.reset();
      retry_at_ = now + std::chrono::seconds(1);
      phase_ = Phase::Retry;
    }
  }

  // Reads the device's diagnosis record (P841, P842, code count) every
  // kDiagPollEvery, and at once when Device_Fault appears. Always inline:
  // the steady scan (operator()) runs it every scan.
  [[gnu::always_inline]] void poll_device_diag(TIME now) {
    if (diag_req_.status() == io::RecordStatus::Done) {
      take_device_diag(diag_req_.data());
      diag_req_.reset();
    } else if (diag_req_.status() == io::RecordStatus::Error) {
      diag_req_.reset();
    }
    const bool fault = (proto_.diag() & diag::kDevFault) != 0;
    if (fault && !dev_fault_prev_) diag_read_wanted_ = true;
    dev_fault_prev_ = fault;
    if (now >= next_diag_read_) diag_read_wanted_ = true;
    if (diag_read_wanted_ && diag_req_.status() == io::RecordStatus::Idle) {
      diag_req_.prepare_read(kNordDiagRecordIndex);
      port.submit(diag_req_);
      diag_read_wanted_ = false;
      next_diag_read_ = now + kDiagPollEvery;
    }
  }

  void take_device_diag(std::span<const std::uint8_t> rec) {
    if (rec.size() < 4) return;
    const std::uint16_t current = io::load_be<std::uint16_t>(rec, 0);
    const std::uint16_t previous = io::load_be<std::uint16_t>(rec, 2);
    // A device without the count (4 bytes) is taken as "count unchanged".
    const std::uint16_t count =
        rec.size() >= 6 ? io::load_be<std::uint16_t>(rec, 4) : dev_code_count_;
    if (current != 0) {
      DIAG_CODE = current;
    } else if (count != dev_code_count_ && previous != 0) {
      DIAG_CODE = previous;  // raised and gone again since the last read
    }
    dev_code_ = current;
    dev_code_count_ = count;
  }

  // a.fill(v) as the copy of a whole array: one store for the F-data
  // lengths of one word (std::array::fill left a compare of its begin and
  // end behind on every steady scan).
  template <std::size_t N>
  static void fill_bytes(std::array<BYTE, N>& a, std::uint8_t v) {
    std::array<BYTE, N> f;
    for (auto& b : f) b = v;
    a = f;
  }

  // The protocol works on OUT_DATA and IN_DATA in place (BYTE is one byte
  // with no padding), not on copies: it keeps the last valid data when no
  // new telegram is due, so it works on the data the block currently shows.
  static_assert(sizeof(BYTE) == 1 && std::is_trivially_copyable_v<BYTE>);
  std::span<const std::uint8_t> out_data() const {
    return {reinterpret_cast<const std::uint8_t*>(OUT_DATA.data()), NOut};
  }
  std::span<std::uint8_t> in_data() {
    return {reinterpret_cast<std::uint8_t*>(IN_DATA.data()), NIn};
  }

  // The steady exchange (nearly every scan in Run) leaves the state Run and
  // the data valid, with PASS_ON off (cmd.pass_on): the outputs for that,
  // without reading the protocol back (the PDU byte stores in the exchange
  // may alias it for the compiler).
  // FModuleOutputs.FollowTheProtocolEveryScan (test_f_module_outputs.cpp).
  void publish_steady() {
    STATE = FHostState::Run;
    PASS_OUT = false;
    QBAD = false;
    ACK_REQ = false;
    IPAR_OK = proto_.ipar_ok();
    DIAG = static_cast<BYTE>(proto_.diag() | (dev_code_ != 0 ? diag::kDevCode : 0));
    fill_bytes(VS_IN, 0xFF);
    fill_bytes(VS_OUT, 0xFF);
  }

  void publish_passive() {
    STATE = proto_.state();
    PASS_OUT = true;
    QBAD = true;
    ACK_REQ = false;
    DIAG = proto_.diag();
    IN_DATA.fill(0);
    VS_IN.fill(0);
    VS_OUT.fill(0);
  }

  FHostProtocol proto_;
  io::RecordRequest fpar_req_;
  io::RecordRequest diag_req_;
  std::array<std::uint8_t, kFParamBlockSize> block_{};
  Phase phase_ = Phase::SendParams;
  TIME retry_at_{};
  bool dev_fault_prev_ = false;
  bool diag_read_wanted_ = false;
  TIME next_diag_read_{};
  std::uint16_t dev_code_ = 0;        // device's current code (P841) at the last read
  std::uint16_t dev_code_count_ = 0;  // device's code count at the last read
  bool restart_after_fault_ = false;
};

}  // namespace plc::safety
