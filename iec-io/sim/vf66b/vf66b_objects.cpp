// Explicit services of the simulated VF66B on the Parameter (0x0F), Motor
// Data (0x28), Control Supervisor (0x29) and AC/DC Drive (0x2A) objects,
// reached through DeviceModel::query_record (explicit_message.hpp).
//
// Only the attributes the manual marks "Supported" exist (Tables 3.3.2,
// 3.4.2, 3.5.2; §13.1.4). Error codes (§11.1, the usual practice it lists):
// 0x16 unknown class or instance, 0x14 an attribute the object does not
// support (all class attributes, instance attrs 1/2, every "Not supported"
// row), 0x08 a service other than Get/Set_Attribute_Single, 0x0E Set on a
// Get attribute, 0x13/0x15 Set data shorter/longer than the attribute's
// type, 0x09 a value outside the attribute's range. [reading] 0x10 (device
// state conflict) for a Set of SpeedScale while the drive runs (J-11 is
// "not changeable during operation"). Every other Set/Get attribute takes a
// Set whatever the output assembly carries: the last write holds until the
// next output message writes it (vf66b_model.hpp).
#include <algorithm>

#include "plc/fb/acdrive/profile_objects.hpp"
#include "plc/fb/acdrive/speed_scale.hpp"
#include "plc/io/explicit_message.hpp"
#include "vf66b/vf66b_model.hpp"

namespace plc::sim {

namespace em = io::explicit_msg;
using acdrive::DriveState;

namespace {

constexpr std::uint8_t kParameterClass = acdrive::kParameterClass;
constexpr std::uint8_t kMotorData = acdrive::kMotorDataClass;
constexpr std::uint8_t kControlSupervisor = acdrive::kControlSupervisorClass;
constexpr std::uint8_t kAcDcDrive = acdrive::kAcDcDriveClass;
using acdrive::AttrType;

io::RecordError err(std::uint8_t general) {
  return static_cast<io::RecordError>(em::error_code(general));
}

std::uint8_t drive_mode_of(Vf66bMode m) {
  // 0x2A attr 6: 1 open-loop speed (V/f), 2 closed-loop speed (vector).
  return m == Vf66bMode::Vf ? 1 : 2;
}

}  // namespace

io::RecordError Vf66bModel::get_attribute(std::uint8_t cls, std::uint8_t attr,
                                          std::span<std::uint8_t> out, std::size_t& length) const {
  const acdrive::ProfileAttr* a = acdrive::find_profile_attr(cls, attr);
  if (!a) return err(em::kAttributeNotSupported);
  std::int32_t v = 0;
  switch (cls << 8 | attr) {
    case kMotorData << 8 | 3:
      v = motor_type_;
      break;
    case kMotorData << 8 | 6:
      v = rated_current_;
      break;
    case kMotorData << 8 | 7:
      v = rated_voltage_;
      break;
    case kControlSupervisor << 8 | 3:
      v = run1_;
      break;
    case kControlSupervisor << 8 | 4:
      v = run2_;
      break;
    case kControlSupervisor << 8 | 5:
      v = net_ctrl_;
      break;
    case kControlSupervisor << 8 | 6:
      v = static_cast<std::uint8_t>(state_);
      break;
    case kControlSupervisor << 8 | 7:
      v = running1_;
      break;
    case kControlSupervisor << 8 | 8:
      v = running2_;
      break;
    case kControlSupervisor << 8 | 9:
      v = ready_attr();
      break;
    case kControlSupervisor << 8 | 10:
      v = faulted_;
      break;
    case kControlSupervisor << 8 | 11:
      v = 0;
      break;  // no warnings modelled
    case kControlSupervisor << 8 | 12:
      v = fault_rst_;
      break;
    case kControlSupervisor << 8 | 15:
      v = ctrl_from_net();
      break;
    case kAcDcDrive << 8 | 3:
      v = at_reference();
      break;
    case kAcDcDrive << 8 | 4:
      v = net_ref_;
      break;
    case kAcDcDrive << 8 | 6:
      v = drive_mode_of(act_.mode);
      break;
    case kAcDcDrive << 8 | 7:
      v = speed_actual_bus();
      break;
    case kAcDcDrive << 8 | 8:
      v = acdrive::is_extended_output(out_inst_) ? bus_of(ext_ref_rpm_) : speed_ref_;
      break;
    case kAcDcDrive << 8 | 22:
      v = speed_scale_;
      break;
    case kAcDcDrive << 8 | 29:
      v = ref_from_net();
      break;
    default:
      return err(em::kAttributeNotSupported);
  }
  const std::size_t n = acdrive::size_of(a->type);
  if (out.size() < n) return err(em::kReplyDataTooLarge);
  out[0] = static_cast<std::uint8_t>(v & 0xFF);
  if (n == 2) out[1] = static_cast<std::uint8_t>((v >> 8) & 0xFF);
  length = n;
  return io::RecordError::None;
}

io::RecordError Vf66bModel::set_attribute(std::uint8_t cls, std::uint8_t attr,
                                          std::span<const std::uint8_t> data) {
  const acdrive::ProfileAttr* a = acdrive::find_profile_attr(cls, attr);
  if (!a) return err(em::kAttributeNotSupported);
  if (!a->settable) return err(em::kAttributeNotSettable);
  const std::size_t n = acdrive::size_of(a->type);
  if (data.size() < n) return err(em::kNotEnoughData);
  if (data.size() > n) return err(em::kTooMuchData);
  std::int32_t v = 0;
  switch (a->type) {
    case AttrType::Bool:
    case AttrType::Usint:
      v = data[0];
      break;
    case AttrType::Sint:
      v = static_cast<std::int8_t>(data[0]);
      break;
    case AttrType::Uint:
      v = data[0] | (data[1] << 8);
      break;
    case AttrType::Int:
      v = static_cast<std::int16_t>(data[0] | (data[1] << 8));
      break;
  }
  if (a->type == AttrType::Bool && v > 1) return err(em::kInvalidAttributeValue);
  const bool running = state_ == DriveState::Enabled || state_ == DriveState::Stopping ||
                       state_ == DriveState::FaultStop;
  switch (cls << 8 | attr) {
    case kMotorData << 8 | 3:
      if (v > 10) return err(em::kInvalidAttributeValue);  // Table 3.3.2: 0..10
      motor_type_ = static_cast<std::uint8_t>(v);
      break;
    case kMotorData << 8 | 6:
      rated_current_ = static_cast<std::uint16_t>(v);
      break;
    case kMotorData << 8 | 7:
      rated_voltage_ = static_cast<std::uint16_t>(v);
      break;
    case kControlSupervisor << 8 | 3:
      run1_ = v != 0;
      break;
    case kControlSupervisor << 8 | 4:
      run2_ = v != 0;
      break;
    case kControlSupervisor << 8 | 5:
      net_ctrl_ = v != 0;
      break;
    case kControlSupervisor << 8 | 12:
      if (v && !fault_rst_) reset_pending_ = true;  // acts on 0->1
      fault_rst_ = v != 0;
      break;
    case kAcDcDrive << 8 | 4:
      net_ref_ = v != 0;
      break;
    case kAcDcDrive << 8 | 6:
      // The control mode is an inverter setting; only the present one is valid.
      if (v != drive_mode_of(act_.mode)) return err(em::kInvalidAttributeValue);
      break;
    case kAcDcDrive << 8 | 8:
      if (acdrive::is_extended_output(out_inst_))
        ext_ref_rpm_ = acdrive::bus_to_rpm(static_cast<std::int16_t>(v), speed_scale_);
      else
        speed_ref_ = static_cast<std::int16_t>(v);
      break;
    case kAcDcDrive << 8 | 22:
      if (running) return err(em::kDeviceStateConflict);
      speed_scale_ = v;  // [reading] volatile: power-up reloads J-11
      break;
    default:
      return err(em::kAttributeNotSupported);
  }
  return io::RecordError::None;
}

io::RecordError Vf66bModel::query_record(std::uint16_t index, std::span<const std::uint8_t> request,
                                         std::span<std::uint8_t> out, std::size_t& length) {
  length = 0;
  if (!em::is_explicit_index(index)) return io::RecordError::InvalidIndex;
  const auto r = em::decode_request(index, request);
  if (!r) return err(em::kNotEnoughData);  // shorter than its path
  std::uint8_t cls = r->path.cls;
  const std::uint8_t inst = r->path.instance;
  std::uint8_t attr = r->path.attribute;
  if (cls != kParameterClass && cls != kMotorData && cls != kControlSupervisor && cls != kAcDcDrive)
    return err(em::kObjectDoesNotExist);
  const bool parameter = cls == kParameterClass;
  const std::size_t max_inst = parameter ? acdrive::kParameterMap.size() : 1;
  if (inst > max_inst) return err(em::kObjectDoesNotExist);
  if (r->service != em::kGetAttributeSingle && r->service != em::kSetAttributeSingle)
    return err(em::kServiceNotSupported);
  // Instance 0 = the class: every class attribute is "Not Support".
  if (inst == 0) return err(em::kAttributeNotSupported);
  if (parameter) {
    if (attr != acdrive::kParameterValueAttr) return err(em::kAttributeNotSupported);
    cls = acdrive::kParameterMap[inst - 1].cls;
    attr = acdrive::kParameterMap[inst - 1].attr;
  }
  if (r->service == em::kGetAttributeSingle) {
    if (!r->data.empty()) return err(em::kTooMuchData);
    return get_attribute(cls, attr, out, length);
  }
  return set_attribute(cls, attr, r->data);
}

}  // namespace plc::sim
