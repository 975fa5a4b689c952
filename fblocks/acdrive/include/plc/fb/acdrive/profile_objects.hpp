// The DNET66-Z's profile objects as the manual gives them
// (toyo-vf66-devicenet.md §3-§6): the "Supported" instance attributes of
// Motor Data (0x28, Table 3.3.2), Control Supervisor (0x29, Table 3.4.2)
// and AC/DC Drive (0x2A, Table 3.5.2), instance 1, with their data types and
// access, and the Parameter object (0x0F, Table 3.2) instances 1..19 with
// the attribute each mirrors ([inf] by name, §3). Everything else the
// tables list is "Not supported". The AcDriveAttribute block takes the
// value types from here; the simulated VF66B serves exactly these.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace plc::acdrive {

inline constexpr std::uint8_t kParameterClass = 0x0F;  // [std] class code, §2
inline constexpr std::uint8_t kMotorDataClass = 0x28;
inline constexpr std::uint8_t kControlSupervisorClass = 0x29;
inline constexpr std::uint8_t kAcDcDriveClass = 0x2A;
inline constexpr std::uint8_t kParameterValueAttr = 1;  // [std] Parameter Value

enum class AttrType : std::uint8_t { Bool, Usint, Sint, Uint, Int };
constexpr std::size_t size_of(AttrType t) {
  return (t == AttrType::Uint || t == AttrType::Int) ? 2 : 1;
}
constexpr bool is_signed(AttrType t) { return t == AttrType::Sint || t == AttrType::Int; }

struct ProfileAttr {
  std::uint8_t cls, attr;
  AttrType type;
  bool settable;  // Set/Get (Get/Set) in the table
};

inline constexpr std::array<ProfileAttr, 21> kProfileAttrs = {{
    {kMotorDataClass, 3, AttrType::Usint, true},           // MotorType
    {kMotorDataClass, 6, AttrType::Uint, true},            // RatedCurrent, 100 mA
    {kMotorDataClass, 7, AttrType::Uint, true},            // RatedVoltage, V
    {kControlSupervisorClass, 3, AttrType::Bool, true},    // Run1
    {kControlSupervisorClass, 4, AttrType::Bool, true},    // Run2
    {kControlSupervisorClass, 5, AttrType::Bool, true},    // NetCtrl
    {kControlSupervisorClass, 6, AttrType::Usint, false},  // State
    {kControlSupervisorClass, 7, AttrType::Bool, false},   // Running1
    {kControlSupervisorClass, 8, AttrType::Bool, false},   // Running2
    {kControlSupervisorClass, 9, AttrType::Bool, false},   // Ready
    {kControlSupervisorClass, 10, AttrType::Bool, false},  // Faulted
    {kControlSupervisorClass, 11, AttrType::Bool, false},  // Warning
    {kControlSupervisorClass, 12, AttrType::Bool, true},   // FaultRst
    {kControlSupervisorClass, 15, AttrType::Bool, false},  // CtrlFromNet
    {kAcDcDriveClass, 3, AttrType::Bool, false},           // AtReference
    {kAcDcDriveClass, 4, AttrType::Bool, true},            // NetRef
    {kAcDcDriveClass, 6, AttrType::Usint, true},           // DriveMode
    {kAcDcDriveClass, 7, AttrType::Int, false},            // SpeedActual
    {kAcDcDriveClass, 8, AttrType::Int, true},             // SpeedRef
    {kAcDcDriveClass, 22, AttrType::Sint, true},           // SpeedScale
    {kAcDcDriveClass, 29, AttrType::Bool, false},          // RefFromNet
}};

constexpr const ProfileAttr* find_profile_attr(std::uint8_t cls, std::uint8_t attr) {
  for (const ProfileAttr& a : kProfileAttrs)
    if (a.cls == cls && a.attr == attr) return &a;
  return nullptr;
}

// Table 3.2: Parameter instance n (1..19) mirrors kParameterMap[n - 1].
struct ParameterMapping {
  std::uint8_t cls, attr;
};
inline constexpr std::array<ParameterMapping, 19> kParameterMap = {{
    {kMotorDataClass, 3},           // 1 Motor Type
    {kMotorDataClass, 6},           // 2 Rated Current
    {kMotorDataClass, 7},           // 3 Rated Voltage
    {kControlSupervisorClass, 5},   // 4 Network Control
    {kControlSupervisorClass, 6},   // 5 Drive State
    {kControlSupervisorClass, 7},   // 6 Running Fwd
    {kControlSupervisorClass, 8},   // 7 Running Rev
    {kControlSupervisorClass, 9},   // 8 Ready
    {kControlSupervisorClass, 10},  // 9 Faulted
    {kControlSupervisorClass, 11},  // 10 Warning
    {kControlSupervisorClass, 12},  // 11 Fault Reset
    {kControlSupervisorClass, 15},  // 12 Control From Net
    {kAcDcDriveClass, 3},           // 13 At Reference
    {kAcDcDriveClass, 4},           // 14 Network Ref
    {kAcDcDriveClass, 6},           // 15 Drive Mode
    {kAcDcDriveClass, 7},           // 16 Speed Actual
    {kAcDcDriveClass, 8},           // 17 Speed Reference
    {kAcDcDriveClass, 22},          // 18 Speed Scale
    {kAcDcDriveClass, 29},          // 19 Ref From Net
}};

// The attribute a (class, instance, attribute) path reaches: a Parameter
// instance resolves to the profile attribute it mirrors. nullptr when the
// path names nothing the DNET66-Z supports.
constexpr const ProfileAttr* resolve_attr(std::uint8_t cls, std::uint8_t instance,
                                          std::uint8_t attr) {
  if (cls == kParameterClass) {
    if (instance < 1 || instance > kParameterMap.size() || attr != kParameterValueAttr)
      return nullptr;
    const ParameterMapping& m = kParameterMap[instance - 1];
    return find_profile_attr(m.cls, m.attr);
  }
  if (instance != 1) return nullptr;
  return find_profile_attr(cls, attr);
}

}  // namespace plc::acdrive
