// A scanner and slaves on an in-memory CAN wire, stepped in lockstep with a
// virtual clock (1 ms per tick): deterministic, no sleeping.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "plc/can/mem_bus.hpp"
#include "plc/devicenet/scanner.hpp"
#include "plc/devicenet/slave.hpp"
#include "plc/io/explicit_message.hpp"

namespace dntest {

using namespace std::chrono_literals;
namespace dn = plc::devicenet;
namespace io = plc::io;
using plc::TIME;

// A test device: inputs = outputs with byte 0 counting steps; a vendor
// object 0x64/1: attr 1 = 20 fixed bytes (a fragmented answer), attr 2
// settable with up to 32 bytes (a fragmented request), attr 3 unsupported.
class TestModel final : public io::DeviceModel {
 public:
  TestModel(std::size_t in, std::size_t out) : in_(in), out_(out) {}
  std::size_t input_size() const override { return in_; }
  std::size_t output_size() const override { return out_; }
  void step(TIME, TIME, std::span<const std::uint8_t> from, std::span<std::uint8_t> to) override {
    for (std::size_t i = 0; i < to.size(); ++i) to[i] = i < from.size() ? from[i] : 0;
    if (!to.empty()) to[0] = static_cast<std::uint8_t>(++steps);
    last_outputs.assign(from.begin(), from.end());
  }
  io::RecordError query_record(std::uint16_t index, std::span<const std::uint8_t> request,
                               std::span<std::uint8_t> out, std::size_t& length) override {
    namespace em = io::explicit_msg;
    const auto r = em::decode_request(index, request);
    length = 0;
    if (!r || r->path.cls != 0x64 || r->path.instance != 1)
      return static_cast<io::RecordError>(em::error_code(em::kObjectDoesNotExist));
    if (r->service == em::kGetAttributeSingle && r->path.attribute == 1) {
      for (std::size_t i = 0; i < 20; ++i) out[i] = static_cast<std::uint8_t>(0xA0 + i);
      length = 20;
      return io::RecordError::None;
    }
    if (r->service == em::kSetAttributeSingle && r->path.attribute == 2) {
      if (r->data.size() > 32)
        return static_cast<io::RecordError>(em::error_code(em::kTooMuchData));
      stored.assign(r->data.begin(), r->data.end());
      return io::RecordError::None;
    }
    if (r->service == em::kGetAttributeSingle && r->path.attribute == 2) {
      std::copy(stored.begin(), stored.end(), out.begin());
      length = stored.size();
      return io::RecordError::None;
    }
    return static_cast<io::RecordError>(em::error_code(em::kAttributeNotSupported));
  }
  void io_connection_lost() override { ++connection_losses; }
  void power_cycle() override { ++power_cycles; }

  std::size_t in_, out_;
  unsigned steps = 0;
  int connection_losses = 0, power_cycles = 0;
  std::vector<std::uint8_t> stored, last_outputs;
};

struct SlaveNode {
  std::unique_ptr<plc::can::Bus> bus;
  std::unique_ptr<dn::Slave> slave;
  TestModel* model = nullptr;
  bool running = true;  // false: the process is gone (not ticked)
};

struct Rig {
  std::shared_ptr<plc::can::MemWire> wire = plc::can::MemWire::create();
  std::unique_ptr<plc::can::Bus> master_bus = wire->attach();
  dn::ScannerConfig cfg;
  std::unique_ptr<dn::Scanner> scanner;
  std::vector<std::unique_ptr<SlaveNode>> slaves;
  TIME now{0};

  explicit Rig(dn::ScannerConfig c = {}) : cfg(c) {
    scanner = std::make_unique<dn::Scanner>(cfg, master_bus.get());
  }
  std::size_t add_device(std::uint8_t mac, std::size_t in, std::size_t out,
                         std::function<void(dn::ScanEntry&)> tweak = {}) {
    dn::ScanEntry e;
    e.name = "dev" + std::to_string(mac);
    e.mac = mac;
    e.input_size = in;
    e.output_size = out;
    if (tweak) tweak(e);
    return scanner->add(e);
  }
  SlaveNode& add_slave(std::uint8_t mac, std::size_t in, std::size_t out,
                       std::uint16_t vendor = 560, std::uint32_t serial = 0) {
    slaves.push_back(make_slave(mac, in, out, vendor, serial));
    return *slaves.back();
  }
  // A slave process restarted: new slave object, same MAC, fresh state.
  SlaveNode& restart_slave(std::size_t i, std::size_t in, std::size_t out) {
    slaves[i] = make_slave(slaves[i]->slave->mac(), in, out, 560, 0);
    return *slaves[i];
  }
  std::unique_ptr<SlaveNode> make_slave(std::uint8_t mac, std::size_t in, std::size_t out,
                                        std::uint16_t vendor, std::uint32_t serial) {
    auto n = std::make_unique<SlaveNode>();
    n->bus = wire->attach();
    dn::SlaveConfig sc;
    sc.mac = mac;
    sc.identity.vendor = vendor;
    sc.identity.product_code = 1713;
    sc.identity.serial = serial ? serial : 0x1000u + mac;
    sc.identity.product_name = "System Weighing Controller";
    auto m = std::make_unique<TestModel>(in, out);
    n->model = m.get();
    n->slave = std::make_unique<dn::Slave>(sc, std::move(m), *n->bus);
    return n;
  }
  void tick() {
    now += 1ms;
    scanner->tick(now);
    for (auto& s : slaves)
      if (s->running) s->slave->tick(now);
  }
  void run(TIME d) {
    const TIME end = now + d;
    while (now < end) tick();
  }
  // Ticks until pred() holds, at most `limit`; returns the time it took, or
  // -1 ms when it never held.
  TIME run_until(const std::function<bool()>& pred, TIME limit) {
    const TIME start = now;
    while (now - start < limit) {
      if (pred()) return now - start;
      tick();
    }
    return pred() ? now - start : TIME(-1ms);
  }
};

}  // namespace dntest
