// Simulated NORD SK TU4-PNS / SK CU4-PNS PROFIsafe F-device (slot 1 "SAFE":
// 8-byte F-PDU each way: 4 bytes F-data, status/control byte, 3-byte CRC2).
// Spec: nord-profisafe.md §8.3 (required behaviour) and §8.4 (fault injection).
//
// FOR TEST BENCHES AND SIMULATION ONLY, NOT CERTIFIED. It shares the
// protocol code with the F-host: the 3-byte CRC2 and the consecutive-number
// semantics rest on real traffic (safety_pdu.hpp); the control/status bits
// and the F-parameter layout are the spec's [SPEC] values and must be
// verified against IEC 61784-3-3.
//
// Behaviour:
//  * F-parameters arrive by record write (kFParamRecordIndex) and are checked
//    in this order: length (5725, fatal), CRC1 (5717), F_Par_Version (5716),
//    F_CRC_Length (5721), F_Block_ID / reserved bits / WD > 10000 (5718),
//    F_SIL above `max_sil` (5715), source (5713), destination range 1..255
//    (5712), destination != own F-address (5711), F_WD_Time 0 (5714),
//    F_iPar_CRC != P840 (5719). A device without a valid F-address (5726)
//    refuses every block with 5726 before any of these checks. The refused
//    write returns the code as the record error. No cyclic exchange until a
//    block passes.
//  * F-address: DIP value (`dip_address` 0..255); P831 (`p831`) when DIP = 0.
//    An effective address of 0 or 65535 is the fatal DIP error 5726.
//  * Cyclic: a request is new when its Toggle_h differs from the last one;
//    a new request is checked with CRC2 for the expected consecutive number
//    (0 after R_cons_nr). A failure sets CE_CRC and fail-safe values; the
//    number advances anyway (the host does too). The watchdog F_WD_Time runs
//    between valid new requests; expiry sets WD_timeout and fail-safe values.
//    CE_CRC / WD_timeout are reported until the host resynchronises with
//    R_cons_nr; FV_activated then stays until OA_Req (spec §8.3 cyclic 4).
//    The device answers each new request once (one response per request).
//  * Errors: q errors passivate per P801 (module: Device_Fault + FV, all
//    outputs off, inputs 0; channel: only that SO off, latched with its code
//    until In 3.7 acknowledges the channel once the cause is gone);
//    they end when the cause is gone and, for safety-function violations and
//    5732-5738, no sooner than 10 s after onset (spec §1.5 [AMBIG] reading).
//    Fatal errors latch Device_Fault + FV until power_cycle().
//  * Diagnosis record kNordDiagRecordIndex (read): P841, P842 and the number
//    of codes raised since power-on (mod 65536), three big-endian UINTs, so
//    that an F-host reading it now and then also learns of a code that came
//    and went between two reads (our format; the manual names no transport).
//  * Drive model: speed (rpm) set by `speed_rpm` or set_speed_rpm(); the
//    encoder position integrates it (pulses per rev from P812, ratio P811),
//    or is set with set_position_inc().
//  * SI1/SI2 pass the P805 filter (a level must be stable for P805 before
//    the device takes it); P806 clock monitoring checks the source set with
//    set_si_source() (5737/5738, held >= 10 s).
// Not modelled: OSSD test pulses P804, output short detection (5732-5736
// only by injection), the non-safe PPO slots.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>

#include "plc/fb/safety/crc2_cache.hpp"
#include "plc/fb/safety/f_parameters.hpp"
#include "plc/io/device_model.hpp"
#include "plc/sim/nord_fe_led.hpp"
#include "plc/sim/nord_iparams.hpp"
#include "plc/sim/nord_response_channel.hpp"
#include "plc/sim/nord_safety_functions.hpp"

namespace plc::sim {

class NordProfisafeModel : public io::DeviceModel {
 public:
  static constexpr std::size_t kPdu = 8;

  explicit NordProfisafeModel(const io::ModelParams& p);

  [[nodiscard]] std::size_t input_size() const override { return kPdu; }
  [[nodiscard]] std::size_t output_size() const override { return kPdu; }
  void step(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
            std::span<std::uint8_t> to_plc) override;
  io::RecordError read_record(std::uint16_t index, std::span<std::uint8_t> out,
                              std::size_t& length) override;
  io::RecordError write_record(std::uint16_t index, std::span<const std::uint8_t> data) override;
  void power_cycle() override;

  // ---- drive and field inputs ----
  void set_speed_rpm(double n) {
    speed_rpm_ = n;
    refresh_inc_per_s();
    at_rest_ = steady_ = false;
  }
  void set_position_inc(double p) {
    position_inc_ = p;
    refresh_integrate();
    at_rest_ = steady_ = false;
  }
  [[nodiscard]] double position_inc() const { return position_inc_; }
  // Raw SI1/SI2 levels; the device sees them through the P805 filter.
  void set_si(bool si1, bool si2) {
    si_raw_ = {si1, si2};
    at_rest_ = steady_ = false;
  }
  // What feeds SI1/SI2 (input 0/1): 0 = static 24 V, 1 = TAKT1, 2 = TAKT2.
  // With P806 assigning a clock, any other source is 5737/5738 (spec §4.5).
  void set_si_source(int input, int clock) {
    si_source_[input & 1] = clock;
    refresh_si_causes();
    at_rest_ = steady_ = false;
  }

  // ---- fault injection (spec §8.4) ----
  // XOR `mask` into byte `byte` of the next n requests the device receives.
  void corrupt_requests(int n, std::size_t byte, std::uint8_t mask);
  // XOR `mask` into byte `byte` of the next n responses the device sends.
  void corrupt_responses(int n, std::size_t byte, std::uint8_t mask);
  // The next n responses are replaced by the one sent two exchanges earlier.
  void repeat_old_responses(int n) {
    repeat_resp_ = n;
    injecting_ = true;
    steady_ = false;
  }
  // The next n received requests are replaced by the one received two
  // exchanges earlier (a replayed request).
  void repeat_old_requests(int n) {
    repeat_req_ = n;
    injecting_ = true;
    steady_ = false;
  }
  // Responses the device sends during the next `how_long` reach the host
  // `d` late; the channel keeps their order (nord_response_channel.hpp).
  void delay_responses(TIME d, TIME how_long) { channel_.delay(d, how_long); }
  // Requests are lost for `d` (the device sees no new telegram).
  void drop_requests(TIME d) {
    drop_for_ = d;
    drop_start_pending_ = true;
    steady_ = false;
  }
  // Stop answering on the bus altogether (SimDevice reports it Offline).
  void stop(bool s) {
    stopped_ = s;
    set_answering_now(!s);
  }
  // The next n responses are computed with a foreign CRC1 (another F-device
  // or address pair answering).
  void answer_as_foreign_device(int n) {
    foreign_ = n;
    injecting_ = true;
    steady_ = false;
  }
  // Device fault: q (acknowledgeable; ends when clear_device_fault() was
  // called and, for 5732-5738, >= 10 s after onset) or fatal (latched).
  void inject_device_fault(std::uint16_t code, bool fatal = false);
  void clear_device_fault() {
    injected_cause_ = false;
    at_rest_ = steady_ = false;
  }
  // A system error (counted in P848; more than 15 is the permanent 5792).
  void inject_system_error();
  // Wrong F-address: new DIP / P831 values, read at the next power_cycle()
  // (the device reads its address only at power-on, spec §6.4).
  void set_dip_address(std::uint16_t dip, std::uint16_t p831 = 0) {
    dip_ = dip;
    p831_ = p831;
  }

  // ---- observation ----
  // For tests of the kept q-error causes: as step() takes them, and each
  // computed from the state (bit i: cause of q error i).
  [[nodiscard]] std::uint32_t q_causes_kept();
  [[nodiscard]] std::uint32_t q_causes_full() const;
  // The F-data Out of a response built now (spec §2.4): as build_response()
  // takes it (kept per change of what it depends on), and put bit by bit.
  [[nodiscard]] std::array<std::uint8_t, 4> response_data();
  [[nodiscard]] std::array<std::uint8_t, 4> response_data_full() const;
  [[nodiscard]] bool ossd(int i) const { return ossd_[i]; }  // 0..2 = SO1..SO3
  // SO1..SO3 as evaluate() sets them, computed bit by bit from what acts
  // now (the request, SO1/SO2 dual channel, P802, channel passivation).
  [[nodiscard]] std::array<bool, 3> ossd_full() const;
  [[nodiscard]] bool fail_safe_active() const;
  [[nodiscard]] bool device_fault() const { return fatal_code_ != 0 || module_fault(); }
  [[nodiscard]] bool fatal() const { return fatal_code_ != 0; }
  [[nodiscard]] bool fparams_ok() const { return !pas_.no_fpar; }
  [[nodiscard]] std::uint16_t f_address() const { return f_address_; }
  [[nodiscard]] std::uint16_t current_code() const { return p841_; }   // P841
  [[nodiscard]] std::uint16_t previous_code() const { return p842_; }  // P842
  // The FE LED now (blink code of the current code, spec §5.6).
  [[nodiscard]] bool fe_led() const { return nord_fe_led(p841_, now_ - code_since_); }
  [[nodiscard]] std::uint32_t cons_nr() const { return cn_; }
  [[nodiscard]] std::uint64_t crc_errors() const { return crc_errors_; }
  [[nodiscard]] std::uint64_t watchdog_expiries() const { return wd_expiries_; }
  [[nodiscard]] std::uint16_t system_errors() const { return p848_; }
  [[nodiscard]] const NordSafetyFunctions& functions() const { return fn_; }
  // What the device took from the valid request cn, if still in its history.
  bool accepted_request(std::uint32_t cn, std::span<std::uint8_t, 4> out) const;
  // The frame the host sees after the last step, with its tag (when the
  // telegram in it was produced, its clean F-data, what was injected).
  [[nodiscard]] const NordFrameTag& shown_frame() const { return channel_.shown_tag(); }
  // Tests: off, evaluate() never skips a step at rest (at_rest_), so a
  // twin without it shows what the skip must leave as it is.
  void set_rest_skip(bool on) {
    rest_skip_ = on;
    at_rest_ = steady_ = false;
  }
  // Tests: off, step() never takes the steady exchange (step_steady()), so
  // a twin without it shows what the steady path must produce.
  void set_steady_path(bool on) {
    steady_allowed_ = on;
    steady_ = false;
  }
  // Tests: the state an exchange writes (protocol, histories, kept
  // response parts, channel frame), equal in two twins fed alike.
  [[nodiscard]] bool same_exchange_state(const NordProfisafeModel& o) const;
  // Tests: how many steps took the steady exchange.
  [[nodiscard]] std::uint64_t steady_steps() const { return steady_steps_; }

 private:
  // q-error slots: one per cause kind.
  enum Q : int {
    kQSls,
    kQSsr,
    kQSdiP,
    kQSdiN,
    kQSos,  // violations 5781-5785
    kQSlsOff,
    kQSsrOff,
    kQSdiPOff,
    kQSdiNOff,
    kQSosOff,  // requested w/o P820 (q)
    kQSo1Off,
    kQSo2Off,
    kQSo3Off,
    kQSi1Off,
    kQSi2Off,  // 5741-5743, 5746-5747
    kQSi1Clock,
    kQSi2Clock,  // 5737, 5738 (P806 clock monitoring)
    kQDiscrepancy,
    kQInjected,
    kQCount
  };
  struct QError {
    std::uint16_t code = 0;
    bool active = false;
    bool cause = false;
    TIME onset{};
    TIME hold{};
    int channel = -1;  // SO index for channel passivation, -1 = module
  };

  void reset_volatile();
  bool handle_request(TIME now, std::span<const std::uint8_t> req);
  bool step_steady(TIME now, const std::uint8_t* in, std::uint8_t* out);
  [[gnu::noinline]] void step_full(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
                                   std::span<std::uint8_t> to_plc);
  void evaluate(TIME now, TIME dt);
  void filter_si(TIME now);
  bool update_q(TIME now);
  void raise_code(std::uint16_t code);
  void build_response();
  std::array<std::uint8_t, 4> data_now();  // response_data(), inline in build_response()
  // Inline: a step asks three times.
  bool passivated() const { return pas_.any() || fatal_code_ != 0; }
  bool module_fault() const { return pas_.module_fault; }
  void refresh_module_fault();
  bool q_cause(int q) const;
  std::uint32_t q_causes();
  void refresh_si_causes();

  NordIParams ip_;
  NordSafetyFunctions fn_;
  std::uint16_t dip_ = 1, p831_ = 0, f_address_ = 1;
  bool address_valid_ = true;  // F-address read at power-on is usable (else 5726)
  int max_sil_ = 3;
  double speed_rpm_ = 0.0, position_inc_ = 0.0;
  // Encoder increments per second at speed_rpm_ (step() integrates it):
  // the first two factors of step()'s product, derived once per change of
  // the speed (the i-parameters are fixed).
  double inc_per_s_ = 0.0;
  void refresh_inc_per_s() {
    inc_per_s_ = speed_rpm_ / 60.0 / ip_.p811 * ip_.pulses();
    refresh_integrate();
  }
  // step() adds inc_per_s_ * dt to the position only when that can change
  // it: P811 > 0 and not (a zero rate, which adds +-0.0, on a position
  // that +-0.0 leaves as it is: any but -0.0 and NaN). Refreshed at each
  // change of either; the position changes otherwise only by that sum.
  bool integrate_ = true;
  void refresh_integrate() {
    const bool kept = inc_per_s_ == 0.0 && !std::isnan(position_inc_) &&
                      !(position_inc_ == 0.0 && std::signbit(position_inc_));
    integrate_ = ip_.p811 > 0.0 && !kept;
  }
  std::array<bool, 2> si_raw_{};  // as wired
  std::array<bool, 2> si_{};      // after the P805 filter
  std::array<bool, 2> si_changing_{};
  std::array<TIME, 2> si_change_since_{};
  std::array<int, 2> si_source_{};
  // q_causes(): the causes given by si_ and si_source_ alone (SI not
  // enabled, P806 clock monitoring; the i-parameters are fixed), refreshed
  // by refresh_si_causes() at each change of either.
  std::uint32_t si_causes_ = 0;
  std::uint16_t config_fatal_ = 0;  // i-parameter / DIP fatal code found at power-on

  // F-parameters / protocol
  // The causes of fail-safe values but a fatal code, one byte each in one
  // 8-byte word: passivated(), asked three times a step, loads it once.
  struct Passivation {
    bool no_fpar = true;        // no F-parameter block accepted
    bool fault_fv = true;       // fail-safe values until OA_Req
    bool host_fv = true;        // host's activate_FV
    bool ce_crc = false;        // CRC2 / consecutive-number error reported
    bool wd_timeout = false;    // watchdog expired, reported
    bool module_fault = false;  // an active q error passivates the module (refresh_module_fault)
    bool unused[2] = {};
    bool any() const {
      std::uint64_t w;
      std::memcpy(&w, this, sizeof w);  // bytes 0 or 1: nonzero iff one is set
      return w != 0;
    }
  };
  static_assert(sizeof(Passivation) == sizeof(std::uint64_t));
  Passivation pas_;
  std::uint64_t pas_word() const {
    std::uint64_t w;
    std::memcpy(&w, &pas_, sizeof w);
    return w;
  }
  std::uint16_t crc1_ = 0;
  TIME wd_{};
  TIME now_{};
  std::uint32_t cn_ = 0;
  bool last_toggle_ = false;
  bool cons_nr_r_ = false;
  TIME t_valid_{};
  std::array<std::uint8_t, 4> requested_{};  // F-data of the last valid request
  // q_causes(): the causes given by requested_ alone, for requested_ ==
  // request_causes_of_ (its bytes; all-zero F-data cause none).
  std::uint32_t request_causes_of_ = 0, request_causes_ = 0;
  std::array<std::uint8_t, 4> applied_{};  // what acts (0 while passivated)
  bool chan_ack_prev_ = false;

  // Errors
  std::array<QError, kQCount> q_{};
  std::uint32_t active_q_ = 0;  // bit i: q_[i].active
  std::uint16_t fatal_code_ = 0;
  std::uint16_t p841_ = 0, p842_ = 0, p848_ = 0;
  std::uint16_t code_events_ = 0;  // codes raised since power-on (diagnosis record)
  TIME code_since_{};              // when p841_ got its value (blink code start)
  bool injected_cause_ = false;
  // SO1..SO3 and a 4th always false: evaluate() reads the four as one word.
  std::array<bool, 4> chan_passive_{};
  TIME discrepancy_since_{};
  bool discrepancy_timing_ = false;
  bool discrepancy_fault_ = false;
  bool respond_pending_ = false;
  // evaluate() at rest: the last full evaluate() ended with both SI at
  // their filtered levels, no SI1/SI2 discrepancy timing (P800[-01]), no
  // safety function enabled (fn_ evaluates SSM alone), no q error active
  // and none with a cause. Such an evaluate() writes back what it found,
  // and so does the next one while nothing it reads has changed but the
  // watchdog's time: pas_ and requested_ (changed by handle_request(),
  // write_record(); compared with rest_pas_ / rest_req_), the rest only
  // through the calls that clear at_rest_ (set_si, set_si_source,
  // set_speed_rpm, set_position_inc, the fault injections, a channel
  // acknowledge, power_cycle() / reset_volatile(), write_record()).
  bool at_rest_ = false;
  bool rest_skip_ = true;  // tests: set_rest_skip(false)
  std::uint32_t rest_req_ = 0;
  std::uint64_t rest_pas_ = 0;
  // build_response(): the F-data (data_now()) and the status bits but
  // Toggle_d and cons_nr_R, as computed after the last full evaluate()
  // (resp_fresh_; cleared by every full evaluate() and reset_volatile()).
  // They are made of pas_, the fatal code, the functions' status bits,
  // SI1/SI2, SO1-3 and the applied request, which change only through a
  // full evaluate() or by calls that make the next evaluate() a full one.
  bool resp_fresh_ = false;
  std::uint8_t resp_status_ = 0;
  std::array<std::uint8_t, 4> resp_data_{};
  // step_steady(), the exchange of the steady state: armed (steady_) at
  // the end of a full step() that accepted a valid new request without
  // R_cons_nr, with no injection ever set (injecting_), evaluate() at rest
  // and build_response()'s parts kept (resp_fresh_). Every call that clears
  // at_rest_ (a change of what evaluate() reads, the F-parameters or the
  // volatile state) clears it too, and so do the injections (injecting_)
  // and drop_requests() (so the steady step needs not look at
  // drop_until_: a drop window starts only in a step after that call).
  // Any full step re-arms or disarms it. steady_req_[t] is the head
  // (bytes 0..4) of a request with Toggle_h = t that the steady path takes:
  // the accepted one, and it with Toggle_h flipped (the requests alternate);
  // steady_resp_[t] the response head (F-data,
  // status byte with Toggle_d = t, cons_nr_R clear).
  bool steady_ = false;
  bool steady_allowed_ = true;  // tests: set_steady_path(false)
  std::array<std::uint64_t, 2> steady_req_{};
  std::array<std::uint64_t, 2> steady_resp_{};
  // Z4 (crc2_z4()) of steady_req_[t] ([t][0]) and steady_resp_[t] ([t][1]).
  std::uint32_t steady_z4_[2][2] = {};
  std::uint64_t steady_steps_ = 0;

  // Outputs
  std::array<bool, 4> ossd_{};  // SO1..SO3, the 4th always false (written as one word)
  // evaluate(): SO1..SO3 (bytes 0..2, 0/1) for each combination of the three
  // SO requests (index bit 0: In 0.0, bit 1: In 3.0, bit 2: In 3.1) before
  // channel passivation; derived once from P800/P802, which are fixed.
  std::array<std::uint32_t, 8> ossd_of_{};
  // data_now(): response_data_full() for the state whose inputs to it
  // are data_key_ (the functions' status bits and SI1/SI2; SO1-3 and the
  // SLS level request), kept from one change of those to the next.
  std::uint64_t data_key_[2] = {~std::uint64_t{0}, ~std::uint64_t{0}};  // no state: first asks
  std::array<std::uint8_t, 4> data_kept_{};
  std::array<std::uint8_t, kPdu> pdu_{};  // the response as sent
  // CRC2 of the requests checked and the responses sent, bit for bit
  // compute_crc2() of this connection (seed crc1_), by its linearity
  // (crc2_cache.hpp): CRC2 = Z4(head) ^ TAIL(consecutive number). The
  // request checked and the response sent in one exchange carry the same
  // number, so TAIL is looked up once (tail_, for cn_ as handle_request()
  // set it; build_response() runs only in that step). Z4 is kept per head
  // (the PDU's bytes 0..4, F-data and control/status byte, as the low 40
  // bits of a word) for the last head of each toggle value; the seed is
  // not in the key, so every change of crc1_ goes through set_crc1(),
  // which empties them. A response with another seed (foreign injection)
  // is computed in full.
  struct Crc2Head {
    std::uint64_t key = ~std::uint64_t{0};  // no head has bits above 40 set: empty
    std::uint32_t z4 = 0;
  };
  std::array<Crc2Head, 2> req_head_{}, resp_head_{};
  std::uint32_t tail_ = 0;
  // kCrc2Tail[1][b1] ^ kCrc2Tail[2][b2] of the number bytes in tail_hi_of_
  // (cn >> 8); both 0 at first, which is that entry for number 0.
  std::uint32_t tail_hi_of_ = 0, tail_hi_ = 0;
  [[gnu::always_inline]] std::uint32_t crc2_tail(std::uint32_t cn) {
    const auto& t = safety::detail::kCrc2Tail;
    const std::uint32_t hi = cn >> 8;
    if (hi != tail_hi_of_) [[unlikely]] {  // every 256th number
      tail_hi_of_ = hi;
      tail_hi_ = t[1][hi & 0xFFu] ^ t[2][(hi >> 8) & 0xFFu];
    }
    return t[0][cn & 0xFFu] ^ tail_hi_;
  }
  // Z4 of the head in `key` (bytes 0..3 F-data, byte 4 control/status)
  // with seed crc1_, from the head kept for it or computed (and kept).
  [[gnu::always_inline]] std::uint32_t crc2_z4(Crc2Head& h, std::uint64_t key) const {
    if (h.key != key) [[unlikely]]
      take_head(h, key, crc1_);
    return h.z4;
  }
  [[gnu::noinline]] static void take_head(Crc2Head& h, std::uint64_t key, std::uint16_t seed);
  void set_crc1(std::uint16_t c) {
    crc1_ = c;
    req_head_ = {};
    resp_head_ = {};
  }
  NordResponseChannel channel_;  // device -> host (not reset by power_cycle)
  std::uint64_t frames_sent_ = 0;

  // History (rings) for repeat injection and the soak oracle. Only the
  // entries written since reset_volatile() are read (head counts them).
  static constexpr std::size_t kHist = 64;
  struct Sent {  // a response as sent (its F-data: pdu bytes 0..3)
    TIME produced{};
    std::array<std::uint8_t, kPdu> pdu{};
  };
  struct Accepted {  // a valid request's number and F-data
    std::uint32_t cn = 0;
    std::array<std::uint8_t, 4> data{};
  };
  std::array<Sent, kHist> sent_{};
  std::array<Accepted, kHist> accepted_{};
  std::size_t sent_head_ = 0, accepted_head_ = 0;
  // The last two new requests received, newest first (a replay takes [1]).
  std::array<std::array<std::uint8_t, kPdu>, 2> req_hist_{};
  std::uint64_t crc_errors_ = 0, wd_expiries_ = 0;

  // Injection state
  int corrupt_req_n_ = 0, corrupt_resp_n_ = 0, repeat_resp_ = 0, repeat_req_ = 0, foreign_ = 0;
  // False: none of the five counts above is > 0 (they are set only by the
  // injection calls, which set this, and zeroed with it by
  // reset_volatile()), so an exchange looks at none of them.
  bool injecting_ = false;
  std::size_t corrupt_req_byte_ = 0, corrupt_resp_byte_ = 0;
  std::uint8_t corrupt_req_mask_ = 0, corrupt_resp_mask_ = 0;
  TIME drop_for_{}, drop_until_{};
  bool drop_start_pending_ = false;
  bool stopped_ = false;
  bool permanent_5792_ = false;
};

}  // namespace plc::sim
