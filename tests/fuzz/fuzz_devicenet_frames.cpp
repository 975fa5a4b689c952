// Fuzz target: the CAN and DeviceNet parsers on the receiving end of a bus
// (iec-io/can/udp_datagram.hpp, iec-io/devicenet/explicit_frame.hpp), and a
// scanner and a slave taking any frames on their wire. The first byte
// picks the part:
//  0 a CAN-over-UDP datagram: decode; what decodes encodes back to the
//    same bytes (property);
//  1 frames into the explicit and I/O reassemblers: a complete message
//    never exceeds its buffer (property), nothing else may happen;
//  2 a scanner with one slave on line, then a rogue node sends any frames
//    (identifiers from the input) for up to 200 ticks of 1 ms: no crash,
//    and a device's inputs change only by a complete poll response of the
//    configured size (property: a lost device's inputs are zero).
#include <array>
#include <chrono>
#include <cstdint>

#include "fuzz_input.hpp"
#include "plc/can/mem_bus.hpp"
#include "plc/can/udp_datagram.hpp"
#include "plc/devicenet/explicit_frame.hpp"
#include "plc/devicenet/scanner.hpp"
#include "plc/devicenet/slave.hpp"

using namespace plc;
using plc::fuzz::FuzzInput;
using namespace std::chrono_literals;
namespace dn = plc::devicenet;

namespace {

can::Frame any_frame(FuzzInput& in) {
  can::Frame f;
  f.id = in.integral<std::uint16_t>() & 0x7FF;
  if (in.byte() == 0xFF) f.id |= can::Frame::kRtr;
  f.len = static_cast<std::uint8_t>(in.byte() % 9);
  for (std::size_t i = 0; i < f.len; ++i) f.data[i] = in.byte();
  return f;
}

void datagram(FuzzInput& in) {
  std::array<std::uint8_t, can::udp::kMaxDatagram> d{};
  const std::size_t n = std::min<std::size_t>(in.remaining(), d.size());
  for (std::size_t i = 0; i < n; ++i) d[i] = in.byte();
  std::array<can::Frame, can::udp::kMaxFramesPerDatagram> frames{};
  const int k = can::udp::decode({d.data(), n}, frames);
  if (k < 0) return;
  std::array<std::uint8_t, can::udp::kMaxDatagram> back{};
  const std::size_t m = can::udp::encode(d[2], {frames.data(), std::size_t(k)}, back);
  if (m != n || !std::equal(back.begin(), back.begin() + static_cast<std::ptrdiff_t>(m), d.begin()))
    __builtin_trap();
}

void reassemblers(FuzzInput& in) {
  dn::ExplicitReassembler ex;
  dn::IoReassembler io(in.byte());
  for (int i = 0; i < 512 && !in.empty(); ++i) {
    const can::Frame f = any_frame(in);
    const auto r = ex.take(f);
    if ((r == dn::ExplicitReassembler::Result::Message ||
         r == dn::ExplicitReassembler::Result::LastFragment) &&
        ex.message().size() > dn::kMaxExplicitMessage)
      __builtin_trap();
    if (io.take(f) == dn::IoReassembler::Result::Complete && io.data().size() > 64 * 7)
      __builtin_trap();
  }
}

class Echo final : public io::DeviceModel {
 public:
  std::size_t input_size() const override { return 12; }
  std::size_t output_size() const override { return 8; }
  void step(TIME, TIME, std::span<const std::uint8_t> from, std::span<std::uint8_t> to) override {
    for (std::size_t i = 0; i < to.size(); ++i) to[i] = i < from.size() ? from[i] : 0x5A;
  }
};

void bus(FuzzInput& in) {
  auto wire = can::MemWire::create();
  auto mbus = wire->attach(), sbus = wire->attach(), rogue = wire->attach();
  dn::ScannerConfig c;
  c.dup_mac_wait = 1ms;
  dn::Scanner sc(c, mbus.get());
  dn::ScanEntry e;
  e.mac = 5;
  e.input_size = 12;
  e.output_size = 8;
  e.epr = 20ms;
  const auto d = sc.add(e);
  dn::SlaveConfig s;
  s.mac = 5;
  s.dup_mac_wait = 1ms;
  dn::Slave slave(s, std::make_unique<Echo>(), *sbus);
  TIME now{0};
  for (int i = 0; i < 200; ++i) {
    now += 1ms;
    sc.tick(now);
    slave.tick(now);
  }
  for (int i = 0; i < 200 && !in.empty(); ++i) {
    const int n = in.byte() % 4;
    for (int k = 0; k < n; ++k) rogue->send(any_frame(in));
    now += 1ms;
    sc.tick(now);
    slave.tick(now);
    const auto inputs = sc.inputs(d);
    if (sc.state(d) != dn::ScanState::Online) {
      for (std::uint8_t b : inputs)
        if (b != 0) __builtin_trap();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzInput in(data, size);
  switch (in.byte() % 3) {
    case 0:
      datagram(in);
      break;
    case 1:
      reassemblers(in);
      break;
    default:
      bus(in);
      break;
  }
  return 0;
}
