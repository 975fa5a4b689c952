// Every PROFIdrive control and status word of the HIWIN E1 telegrams 3, 9 and
// 111 as a typed structure with each bit named after the spec table it comes
// from (shared/specs/hiwin-e1-profinet.md §4). Reserved bits are not stored:
// word() sends 0 in them and from() ignores them on receive (spec §10.1).
//
// Each structure also has the bit masks as constants (k<Name>) so drive code
// that works on raw words (the FBs, the simulated drive) uses the same names.
#pragma once

#include <cstdint>

namespace plc::drive {

constexpr std::uint16_t bit(unsigned n) { return static_cast<std::uint16_t>(1U << n); }
constexpr bool has(std::uint16_t w, std::uint16_t mask) { return (w & mask) != 0; }
constexpr std::uint16_t put(bool on, std::uint16_t mask) { return on ? mask : std::uint16_t{0}; }

// ---- STW1, telegram 3 (spec §4.1, Table 3.3.1.1) ----
struct Stw1Speed {
  static constexpr std::uint16_t kOn = bit(0);           // 1 ON, 0 OFF1
  static constexpr std::uint16_t kNoCoastStop = bit(1);  // 0 = OFF2
  static constexpr std::uint16_t kNoQuickStop = bit(2);  // 0 = OFF3
  static constexpr std::uint16_t kEnableOperation = bit(3);
  static constexpr std::uint16_t kFaultAck = bit(7);  // rising edge
  static constexpr std::uint16_t kControlByPlc = bit(10);
  static constexpr std::uint16_t kDefined = 0x048F;  // bits 4-6, 8, 9, 11-15 reserved

  bool on{};
  bool no_coast_stop{};
  bool no_quick_stop{};
  bool enable_operation{};
  bool fault_ack{};
  bool control_by_plc{};

  static constexpr Stw1Speed from(std::uint16_t w) {
    return {has(w, kOn),       has(w, kNoCoastStop), has(w, kNoQuickStop), has(w, kEnableOperation),
            has(w, kFaultAck), has(w, kControlByPlc)};
  }
  [[nodiscard]] constexpr std::uint16_t word() const {
    return put(on, kOn) | put(no_coast_stop, kNoCoastStop) | put(no_quick_stop, kNoQuickStop) |
           put(enable_operation, kEnableOperation) | put(fault_ack, kFaultAck) |
           put(control_by_plc, kControlByPlc);
  }
  friend constexpr bool operator==(const Stw1Speed&, const Stw1Speed&) = default;
};

// ---- STW1, telegrams 9 and 111 (spec §4.2, Table 3.3.2.1) ----
struct Stw1Pos {
  static constexpr std::uint16_t kOn = bit(0);
  static constexpr std::uint16_t kNoCoastStop = bit(1);
  static constexpr std::uint16_t kNoQuickStop = bit(2);
  static constexpr std::uint16_t kEnableOperation = bit(3);
  static constexpr std::uint16_t kNoRejectTask = bit(4);        // 0 = reject traversing task
  static constexpr std::uint16_t kNoIntermediateStop = bit(5);  // 0 = intermediate stop
  static constexpr std::uint16_t kActivateTask = bit(6);        // rising edge
  static constexpr std::uint16_t kFaultAck = bit(7);            // rising edge
  static constexpr std::uint16_t kJog1 = bit(8);                // positive (swapped by Pt53A)
  static constexpr std::uint16_t kJog2 = bit(9);                // negative (swapped by Pt53A)
  static constexpr std::uint16_t kControlByPlc = bit(10);
  static constexpr std::uint16_t kStartHoming = bit(11);  // 0 = stop homing
  static constexpr std::uint16_t kDefined = 0x0FFF;       // bits 12-15 reserved

  bool on{};
  bool no_coast_stop{};
  bool no_quick_stop{};
  bool enable_operation{};
  bool no_reject_task{};
  bool no_intermediate_stop{};
  bool activate_task{};
  bool fault_ack{};
  bool jog1{};
  bool jog2{};
  bool control_by_plc{};
  bool start_homing{};

  static constexpr Stw1Pos from(std::uint16_t w) {
    return {has(w, kOn),           has(w, kNoCoastStop),
            has(w, kNoQuickStop),  has(w, kEnableOperation),
            has(w, kNoRejectTask), has(w, kNoIntermediateStop),
            has(w, kActivateTask), has(w, kFaultAck),
            has(w, kJog1),         has(w, kJog2),
            has(w, kControlByPlc), has(w, kStartHoming)};
  }
  [[nodiscard]] constexpr std::uint16_t word() const {
    return put(on, kOn) | put(no_coast_stop, kNoCoastStop) | put(no_quick_stop, kNoQuickStop) |
           put(enable_operation, kEnableOperation) | put(no_reject_task, kNoRejectTask) |
           put(no_intermediate_stop, kNoIntermediateStop) | put(activate_task, kActivateTask) |
           put(fault_ack, kFaultAck) | put(jog1, kJog1) | put(jog2, kJog2) |
           put(control_by_plc, kControlByPlc) | put(start_homing, kStartHoming);
  }
  friend constexpr bool operator==(const Stw1Pos&, const Stw1Pos&) = default;
};

// ---- STW2, all telegrams (spec §4.3, Table 3.4.1) ----
struct Stw2 {
  static constexpr std::uint16_t kSignOfLifeMask = 0xF000;  // bits 12-15
  static constexpr unsigned kSignOfLifeShift = 12;
  std::uint8_t controller_sign_of_life{};  // 0..15; bits 0-11 reserved

  static constexpr Stw2 from(std::uint16_t w) {
    return {static_cast<std::uint8_t>((w & kSignOfLifeMask) >> kSignOfLifeShift)};
  }
  [[nodiscard]] constexpr std::uint16_t word() const {
    return static_cast<std::uint16_t>((controller_sign_of_life & 0xF) << kSignOfLifeShift);
  }
  friend constexpr bool operator==(const Stw2&, const Stw2&) = default;
};

// ---- ZSW1, telegram 3 (spec §4.4, Table 3.5.1.1) ----
struct Zsw1Speed {
  static constexpr std::uint16_t kReadyToSwitchOn = bit(0);
  static constexpr std::uint16_t kReadyToOperate = bit(1);
  static constexpr std::uint16_t kOperationEnabled = bit(2);
  static constexpr std::uint16_t kFault = bit(3);
  static constexpr std::uint16_t kNoCoastStop = bit(4);  // 0 = OFF2 active
  static constexpr std::uint16_t kNoQuickStop = bit(5);  // 0 = OFF3 active
  static constexpr std::uint16_t kSwitchOnInhibited = bit(6);
  static constexpr std::uint16_t kWarning = bit(7);
  static constexpr std::uint16_t kSpeedErrorInTolerance = bit(8);
  static constexpr std::uint16_t kControlRequested = bit(9);
  static constexpr std::uint16_t kSpeedReached = bit(10);
  static constexpr std::uint16_t kDefined = 0x07FF;  // bits 11-15 reserved

  bool ready_to_switch_on{};
  bool ready_to_operate{};
  bool operation_enabled{};
  bool fault{};
  bool no_coast_stop{};
  bool no_quick_stop{};
  bool switch_on_inhibited{};
  bool warning{};
  bool speed_error_in_tolerance{};
  bool control_requested{};
  bool speed_reached{};

  static constexpr Zsw1Speed from(std::uint16_t w) {
    return {has(w, kReadyToSwitchOn),       has(w, kReadyToOperate),
            has(w, kOperationEnabled),      has(w, kFault),
            has(w, kNoCoastStop),           has(w, kNoQuickStop),
            has(w, kSwitchOnInhibited),     has(w, kWarning),
            has(w, kSpeedErrorInTolerance), has(w, kControlRequested),
            has(w, kSpeedReached)};
  }
  [[nodiscard]] constexpr std::uint16_t word() const {
    return put(ready_to_switch_on, kReadyToSwitchOn) | put(ready_to_operate, kReadyToOperate) |
           put(operation_enabled, kOperationEnabled) | put(fault, kFault) |
           put(no_coast_stop, kNoCoastStop) | put(no_quick_stop, kNoQuickStop) |
           put(switch_on_inhibited, kSwitchOnInhibited) | put(warning, kWarning) |
           put(speed_error_in_tolerance, kSpeedErrorInTolerance) |
           put(control_requested, kControlRequested) | put(speed_reached, kSpeedReached);
  }
  friend constexpr bool operator==(const Zsw1Speed&, const Zsw1Speed&) = default;
};

// ---- ZSW1, telegrams 9 and 111 (spec §4.5, Table 3.5.2.1) ----
struct Zsw1Pos {
  static constexpr std::uint16_t kReadyToSwitchOn = bit(0);
  static constexpr std::uint16_t kReadyToOperate = bit(1);
  static constexpr std::uint16_t kOperationEnabled = bit(2);
  static constexpr std::uint16_t kFault = bit(3);
  static constexpr std::uint16_t kNoCoastStop = bit(4);
  static constexpr std::uint16_t kNoQuickStop = bit(5);
  static constexpr std::uint16_t kSwitchOnInhibited = bit(6);
  static constexpr std::uint16_t kWarning = bit(7);
  static constexpr std::uint16_t kFollowingErrorInTolerance = bit(8);
  static constexpr std::uint16_t kControlRequested = bit(9);
  static constexpr std::uint16_t kTargetReached = bit(10);
  static constexpr std::uint16_t kHomePositionSet = bit(11);
  static constexpr std::uint16_t kTaskAck = bit(12);  // "rising edge active"
  static constexpr std::uint16_t kMotorStopped = bit(13);
  static constexpr std::uint16_t kDefined = 0x3FFF;  // bits 14-15 reserved

  bool ready_to_switch_on{};
  bool ready_to_operate{};
  bool operation_enabled{};
  bool fault{};
  bool no_coast_stop{};
  bool no_quick_stop{};
  bool switch_on_inhibited{};
  bool warning{};
  bool following_error_in_tolerance{};
  bool control_requested{};
  bool target_reached{};
  bool home_position_set{};
  bool task_ack{};
  bool motor_stopped{};

  static constexpr Zsw1Pos from(std::uint16_t w) {
    return {has(w, kReadyToSwitchOn),
            has(w, kReadyToOperate),
            has(w, kOperationEnabled),
            has(w, kFault),
            has(w, kNoCoastStop),
            has(w, kNoQuickStop),
            has(w, kSwitchOnInhibited),
            has(w, kWarning),
            has(w, kFollowingErrorInTolerance),
            has(w, kControlRequested),
            has(w, kTargetReached),
            has(w, kHomePositionSet),
            has(w, kTaskAck),
            has(w, kMotorStopped)};
  }
  [[nodiscard]] constexpr std::uint16_t word() const {
    return put(ready_to_switch_on, kReadyToSwitchOn) | put(ready_to_operate, kReadyToOperate) |
           put(operation_enabled, kOperationEnabled) | put(fault, kFault) |
           put(no_coast_stop, kNoCoastStop) | put(no_quick_stop, kNoQuickStop) |
           put(switch_on_inhibited, kSwitchOnInhibited) | put(warning, kWarning) |
           put(following_error_in_tolerance, kFollowingErrorInTolerance) |
           put(control_requested, kControlRequested) | put(target_reached, kTargetReached) |
           put(home_position_set, kHomePositionSet) | put(task_ack, kTaskAck) |
           put(motor_stopped, kMotorStopped);
  }
  friend constexpr bool operator==(const Zsw1Pos&, const Zsw1Pos&) = default;
};

// ---- ZSW2 (spec §4.6, Tables 3.6.1.1 and 3.6.2.1) ----
// Telegram 3 defines only the sign-of-life; telegrams 9/111 add bit 11.
struct Zsw2 {
  static constexpr std::uint16_t kPulsesEnabled = bit(11);  // telegrams 9/111 only
  static constexpr std::uint16_t kSignOfLifeMask = 0xF000;
  static constexpr unsigned kSignOfLifeShift = 12;
  bool pulses_enabled{};
  std::uint8_t drive_sign_of_life{};

  // `positioning` = telegram 9/111 (bit 11 defined), else telegram 3.
  static constexpr Zsw2 from(std::uint16_t w, bool positioning = true) {
    return {positioning && has(w, kPulsesEnabled),
            static_cast<std::uint8_t>((w & kSignOfLifeMask) >> kSignOfLifeShift)};
  }
  [[nodiscard]] constexpr std::uint16_t word(bool positioning = true) const {
    return static_cast<std::uint16_t>(put(positioning && pulses_enabled, kPulsesEnabled) |
                                      ((drive_sign_of_life & 0xF) << kSignOfLifeShift));
  }
  friend constexpr bool operator==(const Zsw2&, const Zsw2&) = default;
};

// ---- G1_STW, encoder 1 control word (spec §4.7, Table 3.7.1) ----
// [INF] spec §4.7/§10.3.4: bits 4-6 are one 3-bit command field.
enum class G1Command : std::uint8_t { None = 0, Activate = 1, ReadValue = 2, Cancel = 3 };
struct G1Stw {
  static constexpr std::uint16_t kFunction1 = bit(0);  // reference mark 1
  static constexpr std::uint16_t kFunction2 = bit(1);
  static constexpr std::uint16_t kFunction3 = bit(2);
  static constexpr std::uint16_t kFunction4 = bit(3);
  static constexpr std::uint16_t kCommandMask = 0x0070;  // bits 4-6
  static constexpr unsigned kCommandShift = 4;
  static constexpr std::uint16_t kReservedNotRefSearch = bit(7);  // 0 = reference mark search
  static constexpr std::uint16_t kActivateParking = bit(14);
  static constexpr std::uint16_t kAckSensorError = bit(15);
  static constexpr std::uint16_t kDefined = 0xC0FF;

  bool function1{};
  bool function2{};
  bool function3{};
  bool function4{};
  std::uint8_t command{};      // G1Command value (0..7; 4..7 reserved)
  bool bit7_not_ref_search{};  // 1 = reserved (flying measurement in PROFIdrive)
  bool activate_parking{};
  bool ack_sensor_error{};

  static constexpr G1Stw from(std::uint16_t w) {
    return {has(w, kFunction1),
            has(w, kFunction2),
            has(w, kFunction3),
            has(w, kFunction4),
            static_cast<std::uint8_t>((w & kCommandMask) >> kCommandShift),
            has(w, kReservedNotRefSearch),
            has(w, kActivateParking),
            has(w, kAckSensorError)};
  }
  [[nodiscard]] constexpr std::uint16_t word() const {
    return static_cast<std::uint16_t>(
        put(function1, kFunction1) | put(function2, kFunction2) | put(function3, kFunction3) |
        put(function4, kFunction4) | ((command & 7U) << kCommandShift) |
        put(bit7_not_ref_search, kReservedNotRefSearch) | put(activate_parking, kActivateParking) |
        put(ack_sensor_error, kAckSensorError));
  }
  friend constexpr bool operator==(const G1Stw&, const G1Stw&) = default;
};

// ---- G1_ZSW, encoder 1 status word (spec §4.8, Table 3.8.1) ----
struct G1Zsw {
  static constexpr std::uint16_t kFunction1Active = bit(0);
  static constexpr std::uint16_t kFunction2Active = bit(1);
  static constexpr std::uint16_t kFunction3Active = bit(2);
  static constexpr std::uint16_t kFunction4Active = bit(3);
  static constexpr std::uint16_t kValue1Available = bit(4);
  static constexpr std::uint16_t kValue2Available = bit(5);
  static constexpr std::uint16_t kValue3Available = bit(6);
  static constexpr std::uint16_t kValue4Available = bit(7);
  static constexpr std::uint16_t kErrorAckInProcess = bit(11);
  static constexpr std::uint16_t kParkingActive = bit(14);
  static constexpr std::uint16_t kSensorError = bit(15);
  static constexpr std::uint16_t kDefined = 0xC8FF;

  bool function1_active{};
  bool function2_active{};
  bool function3_active{};
  bool function4_active{};
  bool value1_available{};
  bool value2_available{};
  bool value3_available{};
  bool value4_available{};
  bool error_ack_in_process{};
  bool parking_active{};
  bool sensor_error{};

  static constexpr G1Zsw from(std::uint16_t w) {
    return {has(w, kFunction1Active), has(w, kFunction2Active), has(w, kFunction3Active),
            has(w, kFunction4Active), has(w, kValue1Available), has(w, kValue2Available),
            has(w, kValue3Available), has(w, kValue4Available), has(w, kErrorAckInProcess),
            has(w, kParkingActive),   has(w, kSensorError)};
  }
  [[nodiscard]] constexpr std::uint16_t word() const {
    return put(function1_active, kFunction1Active) | put(function2_active, kFunction2Active) |
           put(function3_active, kFunction3Active) | put(function4_active, kFunction4Active) |
           put(value1_available, kValue1Available) | put(value2_available, kValue2Available) |
           put(value3_available, kValue3Available) | put(value4_available, kValue4Available) |
           put(error_ack_in_process, kErrorAckInProcess) | put(parking_active, kParkingActive) |
           put(sensor_error, kSensorError);
  }
  friend constexpr bool operator==(const G1Zsw&, const G1Zsw&) = default;
};

// ---- SATZANW, position block selection, telegram 9 (spec §4.9, Table 3.9.1) ----
// Only the MDI submode works; traversing blocks (bits 0-14) are not supported.
struct Satzanw {
  static constexpr std::uint16_t kActivateMdi = bit(15);
  static constexpr std::uint16_t kDefined = 0x8000;
  bool activate_mdi{};
  static constexpr Satzanw from(std::uint16_t w) { return {has(w, kActivateMdi)}; }
  [[nodiscard]] constexpr std::uint16_t word() const { return put(activate_mdi, kActivateMdi); }
  friend constexpr bool operator==(const Satzanw&, const Satzanw&) = default;
};

// ---- AKTSATZ, selected position block, telegram 9 (spec §4.10, Table 3.10.1) ----
struct Aktsatz {
  static constexpr std::uint16_t kMdiActive = bit(15);
  static constexpr std::uint16_t kDefined = 0x8000;
  bool mdi_active{};
  static constexpr Aktsatz from(std::uint16_t w) { return {has(w, kMdiActive)}; }
  [[nodiscard]] constexpr std::uint16_t word() const { return put(mdi_active, kMdiActive); }
  friend constexpr bool operator==(const Aktsatz&, const Aktsatz&) = default;
};

// ---- MDI_MODE, telegram 9 (spec §4.11, Table 3.11.1) ----
// Bits 1-2 (modulo direction in PROFIdrive) are reserved on the E1.
struct MdiMode {
  static constexpr std::uint16_t kAbsolute = bit(0);  // 0 = relative
  static constexpr std::uint16_t kDefined = 0x0001;
  bool absolute{};
  static constexpr MdiMode from(std::uint16_t w) { return {has(w, kAbsolute)}; }
  [[nodiscard]] constexpr std::uint16_t word() const { return put(absolute, kAbsolute); }
  friend constexpr bool operator==(const MdiMode&, const MdiMode&) = default;
};

// ---- POS_STW1, telegram 111 (spec §4.12, Table 3.12.1) ----
struct PosStw1 {
  static constexpr std::uint16_t kAbsolute = bit(8);  // 0 = relative
  static constexpr std::uint16_t kActivateMdi = bit(15);
  static constexpr std::uint16_t kDefined = 0x8100;
  bool absolute{};
  bool activate_mdi{};
  static constexpr PosStw1 from(std::uint16_t w) {
    return {has(w, kAbsolute), has(w, kActivateMdi)};
  }
  [[nodiscard]] constexpr std::uint16_t word() const {
    return put(absolute, kAbsolute) | put(activate_mdi, kActivateMdi);
  }
  friend constexpr bool operator==(const PosStw1&, const PosStw1&) = default;
};

// ---- POS_STW2, telegram 111 (spec §4.13, Table 3.13.1) ----
struct PosStw2 {
  static constexpr std::uint16_t kSetReferencePoint = bit(1);
  static constexpr std::uint16_t kDefined = 0x0002;
  bool set_reference_point{};
  static constexpr PosStw2 from(std::uint16_t w) { return {has(w, kSetReferencePoint)}; }
  [[nodiscard]] constexpr std::uint16_t word() const {
    return put(set_reference_point, kSetReferencePoint);
  }
  friend constexpr bool operator==(const PosStw2&, const PosStw2&) = default;
};

// ---- POS_ZSW1, telegram 111 (spec §4.14, Table 3.14.1) ----
struct PosZsw1 {
  static constexpr std::uint16_t kNegOvertravel = bit(8);
  static constexpr std::uint16_t kPosOvertravel = bit(9);
  static constexpr std::uint16_t kJogActive = bit(10);
  static constexpr std::uint16_t kHomingActive = bit(11);
  static constexpr std::uint16_t kMdiActive = bit(15);
  static constexpr std::uint16_t kDefined = 0x8F00;
  bool negative_overtravel{};
  bool positive_overtravel{};
  bool jog_active{};
  bool homing_active{};
  bool mdi_active{};
  static constexpr PosZsw1 from(std::uint16_t w) {
    return {has(w, kNegOvertravel), has(w, kPosOvertravel), has(w, kJogActive),
            has(w, kHomingActive), has(w, kMdiActive)};
  }
  [[nodiscard]] constexpr std::uint16_t word() const {
    return put(negative_overtravel, kNegOvertravel) | put(positive_overtravel, kPosOvertravel) |
           put(jog_active, kJogActive) | put(homing_active, kHomingActive) |
           put(mdi_active, kMdiActive);
  }
  friend constexpr bool operator==(const PosZsw1&, const PosZsw1&) = default;
};

// ---- POS_ZSW2, telegram 111 (spec §4.15, Table 3.15.1) ----
struct PosZsw2 {
  static constexpr std::uint16_t kSetpointAvailable = bit(2);
  static constexpr std::uint16_t kMovingForward = bit(4);
  static constexpr std::uint16_t kMovingBackward = bit(5);
  static constexpr std::uint16_t kTraversingActive = bit(15);
  static constexpr std::uint16_t kDefined = 0x8034;
  bool setpoint_available{};
  bool moving_forward{};
  bool moving_backward{};
  bool traversing_active{};
  static constexpr PosZsw2 from(std::uint16_t w) {
    return {has(w, kSetpointAvailable), has(w, kMovingForward), has(w, kMovingBackward),
            has(w, kTraversingActive)};
  }
  [[nodiscard]] constexpr std::uint16_t word() const {
    return put(setpoint_available, kSetpointAvailable) | put(moving_forward, kMovingForward) |
           put(moving_backward, kMovingBackward) | put(traversing_active, kTraversingActive);
  }
  friend constexpr bool operator==(const PosZsw2&, const PosZsw2&) = default;
};

// ---- MELDW, telegram 111 (spec §4.16, Table 3.16.1) ----
struct Meldw {
  static constexpr std::uint16_t kTorqueLimitNotActive = bit(1);
  static constexpr std::uint16_t kNoMotorOverloadWarning = bit(6);
  static constexpr std::uint16_t kNoI2tWarning = bit(7);
  static constexpr std::uint16_t kSpeedDeviationInTolerance = bit(8);  // not functional: always 1
  static constexpr std::uint16_t kControllerEnabled = bit(11);
  static constexpr std::uint16_t kDriveReady = bit(12);
  static constexpr std::uint16_t kPulsesEnabled = bit(13);
  static constexpr std::uint16_t kDefined = 0x39C2;
  bool torque_limit_not_active{};
  bool no_motor_overload_warning{};
  bool no_i2t_warning{};
  bool speed_deviation_in_tolerance{};
  bool controller_enabled{};
  bool drive_ready{};
  bool pulses_enabled{};
  static constexpr Meldw from(std::uint16_t w) {
    return {has(w, kTorqueLimitNotActive), has(w, kNoMotorOverloadWarning),
            has(w, kNoI2tWarning),         has(w, kSpeedDeviationInTolerance),
            has(w, kControllerEnabled),    has(w, kDriveReady),
            has(w, kPulsesEnabled)};
  }
  [[nodiscard]] constexpr std::uint16_t word() const {
    return put(torque_limit_not_active, kTorqueLimitNotActive) |
           put(no_motor_overload_warning, kNoMotorOverloadWarning) |
           put(no_i2t_warning, kNoI2tWarning) |
           put(speed_deviation_in_tolerance, kSpeedDeviationInTolerance) |
           put(controller_enabled, kControllerEnabled) | put(drive_ready, kDriveReady) |
           put(pulses_enabled, kPulsesEnabled);
  }
  friend constexpr bool operator==(const Meldw&, const Meldw&) = default;
};

}  // namespace plc::drive
