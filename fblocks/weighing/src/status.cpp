#include "plc/fb/weighing/status.hpp"

namespace plc::weighing {

void PR5510_Status::operator()(const ScanContext&) {
  Valid = Device != nullptr && Device->Online;
  if (!Valid) return;
  const StatusBits& s = Device->status();
  Limit1 = s.Limit1;
  Limit2 = s.Limit2;
  Limit3 = s.Limit3;
  Out1 = s.Out1;
  Out2 = s.Out2;
  Out3 = s.Out3;
  PowerFail = s.PowerFail;
  WriteActive = s.WriteActive;
  TestActive = s.TestActive;
  CalChanged = s.CalChanged;
  TareActive = s.TareActive;
  Inp1 = s.Inp1;
  Inp2 = s.Inp2;
  Inp3 = s.Inp3;
  CmdError = s.CmdError;
  CmdBusy = s.CmdBusy;
  AduError = s.AduError;
  AboveFsd = s.AboveFsd;
  Overload = s.Overload;
  BelowZero = s.BelowZero;
  CenterZero = s.CenterZero;
  InsideZsr = s.InsideZsr;
  StandStill = s.StandStill;
  Dimmed = s.Dimmed;
}

}  // namespace plc::weighing
