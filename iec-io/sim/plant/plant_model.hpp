// `plant`: a linear process for the sim plugin (a heated oven, a tank, a
// conveyor's load), configured in the cell YAML (docs/config.md, "The plant
// model") as state space or as a transfer function, discretised exactly for
// its own sample time (zoh_discretisation.hpp), with dead time, scaled and
// saturated inputs and outputs, seeded measurement noise, and couplings to
// other devices of the same sim plugin (plc/io/device_peers.hpp).
//
// Process data, in channel order:
//   PLC -> device (%Q): the inputs u1..um that come from the PLC (no `from`)
//   device -> PLC (%I): the outputs y1..yp that go to the PLC (no `to`)
// each as many bytes as its type.
//
// One step(dt) runs as many plant samples as fit into the time that passed
// (the remainder carries over), with the inputs read once at its start:
// the PLC's outputs and the peers' bytes hold over the whole step, as a
// zero-order hold does. Then the outputs are measured (plus noise), scaled
// and written. A plant whose state stops being finite (only possible with
// allow_unstable) freezes with its last outputs.
#pragma once

#include <memory>
#include <vector>

#include "plant/plant_channel.hpp"
#include "plc/io/device_model.hpp"
#include "plc/sim/plant/linear_plant.hpp"
#include "plc/sim/seeded_noise.hpp"

namespace plc::plant {

class PlantModel final : public io::DeviceModel, public io::PeerCoupledModel {
 public:
  // Throws ParamError naming the key (sizes that do not fit, an unstable or
  // non-finite discretisation, a channel the plant does not have, ...).
  explicit PlantModel(const io::ModelParams& p);

  std::size_t input_size() const override { return in_size_; }
  std::size_t output_size() const override { return out_size_; }
  void step(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
            std::span<std::uint8_t> to_plc) override;

  void bind_peers(const io::DevicePeers& peers) override;
  bool needs_peers() const override;

  // The plant itself, for tests: state, outputs in engineering units.
  [[nodiscard]] const LinearPlant& plant() const { return *plant_; }
  [[nodiscard]] bool diverged() const { return diverged_; }

 private:
  struct Input {
    ChannelCodec codec;
    ChannelPlace place;
    std::string key;  // "u1"
  };
  struct Output {
    ChannelCodec codec;
    ChannelPlace place;
    double offset = 0;  // engineering units, added to C x + D u
    double noise = 0;   // sigma, engineering units
    std::string key;    // "y1"
  };

  std::unique_ptr<LinearPlant> plant_;
  std::vector<Input> inputs_;
  std::vector<Output> outputs_;
  std::vector<double> u_;       // engineering units, per input
  std::vector<double> y_meas_;  // last measured outputs (with offset and noise)
  std::size_t in_size_ = 0, out_size_ = 0;
  TIME h_{};
  TIME pending_{};  // time passed that has not made a whole sample yet
  sim::SeededNoise noise_;
  bool diverged_ = false;
  bool measured_ = false;
};

}  // namespace plc::plant
