// Couplings between simulated devices: a model that reads another device's
// bytes (a conveyor load driven by a drive's actual speed, a tank fed by a
// valve that the PLC commands through another device) or writes into
// another device's inputs (a sensor wired to a remote I/O card).
//
// The host decides the order, and the order makes it deterministic: the
// sim plugin steps its devices in config order, and it offers a model only
// the devices listed before it in the same plugin (bind_peers is called
// once, right after the model is made). So within one step a coupled model
// reads what its sources delivered in this same step (their inputs, i.e.
// device -> PLC) or what the PLC published to them (their outputs), and
// what it writes into a source's inputs lands after that source stepped,
// before the PLC latches them. No coupling waits, none has a step of
// latency, and two runs give the same bytes.
//
// A separate interface, not a DeviceModel member: hosts that cannot offer
// peers (a PROFINET or DeviceNet device simulator hosts one model) never
// call it, and DeviceModel's layout (the cell-library ABI) stays as it is.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace plc::io {

class DevicePeers {
 public:
  struct Peer {
    std::span<std::uint8_t> inputs;   // device -> PLC, as the PLC latches them
    std::span<std::uint8_t> outputs;  // PLC -> device, as the PLC published them
  };
  virtual ~DevicePeers() = default;
  [[nodiscard]] virtual std::optional<Peer> find(std::string_view name) const = 0;
  // The devices a model may couple to, for error messages.
  [[nodiscard]] virtual std::vector<std::string> names() const = 0;
};

class PeerCoupledModel {
 public:
  virtual ~PeerCoupledModel() = default;
  // Resolves the model's couplings: throws ParamError naming the key of an
  // unknown device or of a byte range that does not fit it. The spans stay
  // valid for the host's lifetime.
  virtual void bind_peers(const DevicePeers& peers) = 0;
  // Whether the config asks for couplings at all. A host that cannot offer
  // peers should refuse such a model: unbound, a coupled input reads 0 and
  // a coupled output goes nowhere. (The sim plugin is the only host that
  // creates coupled models today: pndevsim and dnslave do not link the
  // plant model, and the profinet plugin needs a description of the
  // model's IO data, which no built-in one has.)
  [[nodiscard]] virtual bool needs_peers() const = 0;
};

}  // namespace plc::io
