// A simulated device: one class, no transport in it.
//
// It takes the PLC's output bytes and a time step and gives input bytes, and
// it answers acyclic record requests. The in-process `sim` plugin hosts it;
// protocol-level device simulators (PROFINET device, DeviceNet slave) can host
// the same class. Models are deterministic: the same outputs and steps give
// the same inputs, bit for bit (seed any noise from params).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "plc/io/model_params.hpp"
#include "plc/io/record_request.hpp"
#include "plc/types.hpp"

namespace plc::io {

class DeviceModel {
 public:
  virtual ~DeviceModel() = default;

  // Cyclic data sizes in bytes: device -> PLC (%I) and PLC -> device (%Q).
  [[nodiscard]] virtual std::size_t input_size() const = 0;
  [[nodiscard]] virtual std::size_t output_size() const = 0;

  // Advance the device by dt to time `now` with the latest PLC outputs, and
  // write the device's current inputs. Called every plugin step.
  virtual void step(TIME now, TIME dt, std::span<const std::uint8_t> from_plc,
                    std::span<std::uint8_t> to_plc) = 0;

  // step() for a host whose transport delivers the outputs as discrete I/O
  // messages (a DeviceNet slave's polled I/O): `new_message` says whether
  // from_plc holds an I/O message consumed since the previous step; without
  // one, from_plc is the last message again. A model whose objects can also
  // be written by explicit services uses this to let an explicit Set stand
  // until the next I/O message (Vf66bModel). The default ignores the flag:
  // the outputs apply at every step, as in the in-process sim plugin, which
  // calls step() and delivers the outputs every cycle.
  virtual void step_io(TIME now, TIME dt, std::span<const std::uint8_t> from_plc, bool new_message,
                       std::span<std::uint8_t> to_plc) {
    (void)new_message;
    step(now, dt, from_plc, to_plc);
  }

  // Acyclic services. Read: fill `out`, set `length`; return None or an
  // error. The default refuses every index.
  virtual RecordError read_record(std::uint16_t index, std::span<std::uint8_t> out,
                                  std::size_t& length);
  virtual RecordError write_record(std::uint16_t index, std::span<const std::uint8_t> data);
  // A read that carries request bytes (RecordRequest::prepare_read(index,
  // request); DeviceNet explicit services, explicit_message.hpp). The default
  // serves a read without request bytes through read_record and refuses one
  // with them (the model does not know such requests).
  virtual RecordError query_record(std::uint16_t index, std::span<const std::uint8_t> request,
                                   std::span<std::uint8_t> out, std::size_t& length);

  // Whether the device answers on the bus now (fault injection "stop
  // answering" turns this off; the plugin then reports the device Offline and
  // stops updating its inputs). A kept flag, not a virtual call: the host
  // asks every step (the sim plugin: every device, every ms). A model sets
  // it with set_answering_now() whenever what it depends on changes.
  [[nodiscard]] bool answering() const { return answering_now_; }

  // Power cycle: volatile state lost, non-volatile state (e.g. an absolute
  // encoder's multi-turn count) kept.
  virtual void power_cycle() {}

  // The hosting transport lost the I/O connection (its connection timeout
  // expired, e.g. a DeviceNet expected-packet-rate timeout). Default: nothing.
  virtual void io_connection_lost() {}

 protected:
  void set_answering_now(bool on) { answering_now_ = on; }

 private:
  bool answering_now_ = true;
};

using DeviceModelFactory = std::function<std::unique_ptr<DeviceModel>(const ModelParams&)>;

// Models are found by name (the `model:` key of a device in the cell config).
class DeviceModelRegistry {
 public:
  static DeviceModelRegistry& instance();
  void add(const std::string& name, DeviceModelFactory f);
  [[nodiscard]] const DeviceModelFactory* find(const std::string& name) const;
  [[nodiscard]] std::vector<std::string> names() const;
  // While a cell library loads, its registrations are collected here
  // instead of taking effect (plc/cell_library.hpp): they count only once
  // its ABI version has been checked. nullptr: add() registers.
  void set_capture(std::map<std::string, DeviceModelFactory>* c) { capture_ = c; }

 private:
  std::map<std::string, DeviceModelFactory> factories_;
  std::map<std::string, DeviceModelFactory>* capture_ = nullptr;
};

// Registers a model class constructible from `const ModelParams&`:
//   PLC_REGISTER_DEVICE_MODEL("first_order", FirstOrderPlant)
// Put it in a .cpp of an OBJECT library (static archives drop unused objects).
#define PLC_REGISTER_DEVICE_MODEL(name, Class)                                             \
  namespace {                                                                              \
  const bool plc_model_registered_##Class = [] {                                           \
    ::plc::io::DeviceModelRegistry::instance().add(                                        \
        name, [](const ::plc::io::ModelParams& p) { return std::make_unique<Class>(p); }); \
    return true;                                                                           \
  }();                                                                                     \
  }

}  // namespace plc::io
