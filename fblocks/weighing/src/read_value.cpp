#include "plc/fb/weighing/read_value.hpp"

namespace plc::weighing {

void PR5510_ReadValue::fail(std::uint16_t id) {
  Error = true;
  ErrorID = id;
  Busy = false;
  Valid = false;
}

void PR5510_ReadValue::operator()(const ScanContext&) {
  if (!Enable) {
    Valid = Busy = Error = false;
    ErrorID = error_id::kNone;
    return;
  }
  if (Error) return;  // held until Enable goes FALSE
  if (Device == nullptr) return fail(error_id::kNoDevice);
  if (slot_ == PR5510_Device::kNoSlot) {
    slot_ = Device->attach();
    if (slot_ == PR5510_Device::kNoSlot) return fail(error_id::kTooManyClients);
  }
  if (!is_defined_read_code(Code)) return fail(error_id::kInvalidCode);
  if (!Device->Online) return fail(error_id::kDeviceOffline);
  if (const std::uint16_t e = Device->read_error(slot_); e != error_id::kNone) return fail(e);
  if (Code != last_code_) {
    Valid = false;  // a new code: the old value no longer applies
    last_code_ = Code;
  }
  Busy = true;
  if (Device->read_valid(slot_, Code)) {
    Value = Device->read_dint();
    ValueReal = Device->read_real();
    Raw = Device->read_raw();
    Valid = true;
    ++Updates;
  }
  Device->request_read(slot_, Code);
}

}  // namespace plc::weighing
