// Table 5.1.1 of the E1 manual (spec §8): fault number (PNU 947), fault code
// (PNU 945 and FAULT_CODE, the hex digits the 7-segment display shows, read
// as a hex number: "0b0" -> 0x00B0, "8d0" -> 0x08D0) and alarm name.
#include <cstdint>

#include "hiwin_e1/hiwin_e1_model.hpp"

namespace plc::sim {

namespace {
struct FaultRow {
  std::uint16_t number;
  std::uint16_t code;
  const char* name;
};
constexpr FaultRow kFaults[] = {
    {4, 0x024, "System alarm 1"},
    {5, 0x025, "System alarm 2"},
    {6, 0x030, "Main circuit malfunction"},
    {7, 0x040, "Parameter setting error"},
    {11, 0x050, "Combination error"},
    {12, 0x070, "Motor change detected"},
    {14, 0x0B0, "Invalid servo-on command"},
    {15, 0x100, "Overcurrent detected"},
    {16, 0x320, "Regenerative energy overflow"},
    {17, 0x400, "Overvoltage"},
    {18, 0x410, "Undervoltage"},
    {19, 0x510, "Overspeed"},
    {20, 0x511, "Encoder pulse output overspeed"},
    {24, 0x710, "Overload (instantaneous maximum load)"},
    {25, 0x720, "Overload (continuous maximum load)"},
    {30, 0x7A2, "Power board temperature error"},
    {33, 0x800, "Encoder absolute position lost"},
    {34, 0x810, "Encoder battery undervoltage"},
    {35, 0x820, "Encoder communication error"},
    {36, 0x830, "Encoder data error"},
    {37, 0x840, "Encoder communication CRC error"},
    {38, 0x850, "Encoder counting error"},
    {39, 0x860, "Encoder data writing error"},
    {40, 0x870, "Encoder overheating"},
    {41, 0x880, "Incremental encoder signal phase order error"},
    {42, 0x890, "Excellent Smart Cube (ESC) - incremental encoder disconnection"},
    {43, 0x8A0, "First set of encoder - ESC signal error"},
    {44, 0x8B0, "First set of encoder - encoder signal error"},
    {45, 0x8C0, "Second set of encoder - ESC signal error"},
    {46, 0x8D0, "Second set of encoder - encoder signal error"},
    {47, 0x8E0, "Digital encoder disconnection"},
    {48, 0x8F0, "ESC internal error"},
    {49, 0x861, "Motor overheating"},
    {50, 0xB10, "Velocity command A/D converter error"},
    {52, 0xB20, "Torque command A/D converter error"},
    {53, 0xB33, "Current detection malfunction"},
    {54, 0xC10, "Motor out of control"},
    {55, 0xC20, "Phase detection error"},
    {56, 0xC21, "Hall sensor error"},
    {58, 0xC50, "Electrical angle detection failure"},
    {59, 0xC51, "Overtravel detected during electrical angle detection"},
    {60, 0xC52, "Electrical angle detection incomplete"},
    {62, 0xD00, "Position deviation overflow"},
    {65, 0xD10, "Motor-load position deviation overflow"},
    {66, 0xEB0, "Safety function alarm"},
    {67, 0xEB1, "Safety function signal input timing error"},
    {68, 0xEB2, "Safety function module error"},
    {69, 0xF10, "Power cable open phase"},
    {70, 0xF50, "Motor main circuit cable disconnection"},
    {71, 0xFA0, "Encoder power error"},
    {72, 0xFB0, "Fieldbus communication hardware malfunction"},
    {73, 0xFB1, "Fieldbus communication error"},
    {74, 0xFC0, "Group control system communication error"},
    {75, 0xFC1, "Slave axis error in group control system"},
    {76, 0x891, "Incremental encoder signal error"},
    {77, 0xFB2, "Fieldbus communication setup error"},
};
static_assert(sizeof(kFaults) / sizeof(kFaults[0]) == 56, "Table 5.1.1 has 56 rows");
}  // namespace

std::uint16_t e1_fault_number(std::uint16_t code) {
  for (const auto& f : kFaults)
    if (f.code == code) return f.number;
  return 0;
}

const char* e1_alarm_name(std::uint16_t code) {
  for (const auto& f : kFaults)
    if (f.code == code) return f.name;
  return "";
}

}  // namespace plc::sim
