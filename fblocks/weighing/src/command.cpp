#include "plc/fb/weighing/command.hpp"

#include "plc/fb/weighing/window_job.hpp"

namespace plc::weighing {

void PR5510_Command::operator()(const ScanContext&) {
  run_window_job(
      {Execute, Done, Busy, Error, ErrorID, prev_execute_}, Device, slot_,
      static_cast<unsigned>(Command) < kCommandBitCount,
      [this] {
        Device->ack_command(slot_);
        Device->request_command(slot_, Command);
      },
      [this]() -> std::pair<JobResult, std::uint16_t> {
        switch (Device->command_status(slot_)) {
          case CommandStatus::Done:
            Device->ack_command(slot_);
            return {JobResult::Done, 0};
          case CommandStatus::Error: {
            const std::uint16_t e = Device->command_error(slot_);
            Device->ack_command(slot_);
            return {JobResult::Error, e};
          }
          default:
            return {JobResult::Pending, 0};
        }
      });
}

}  // namespace plc::weighing
