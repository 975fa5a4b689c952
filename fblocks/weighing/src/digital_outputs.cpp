#include "plc/fb/weighing/digital_outputs.hpp"

namespace plc::weighing {

void PR5510_DigitalOutputs::operator()(const ScanContext&) {
  Valid = Device != nullptr && Device->Online;
  if (Device == nullptr) return;
  if (Enable) {
    Device->set_output(OutputBit::Out1, Out1);
    Device->set_output(OutputBit::Out2, Out2);
    Device->set_output(OutputBit::Out3, Out3);
  }
  const StatusBits& s = Device->status();
  Out1State = s.Out1;
  Out2State = s.Out2;
  Out3State = s.Out3;
}

}  // namespace plc::weighing
