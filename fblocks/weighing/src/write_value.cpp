#include "plc/fb/weighing/write_value.hpp"

#include <bit>

#include "plc/fb/weighing/window_job.hpp"

namespace plc::weighing {

void PR5510_WriteValue::operator()(const ScanContext&) {
  run_window_job(
      {Execute, Done, Busy, Error, ErrorID, prev_execute_}, Device, slot_,
      is_defined_write_code(Code),
      [this] {
        const std::uint32_t raw =
            UseReal ? std::bit_cast<std::uint32_t>(ValueReal) : static_cast<std::uint32_t>(Value);
        Device->ack_write(slot_);
        Device->request_write(slot_, Code, raw);
      },
      [this]() -> std::pair<JobResult, std::uint16_t> {
        switch (Device->write_status(slot_)) {
          case WriteStatus::Done:
            Device->ack_write(slot_);
            return {JobResult::Done, 0};
          case WriteStatus::Error: {
            const std::uint16_t e = Device->write_error(slot_);
            Device->ack_write(slot_);
            return {JobResult::Error, e};
          }
          default:
            return {JobResult::Pending, 0};
        }
      });
}

}  // namespace plc::weighing
