// What the HMI targets (hmi_commands, hmi_ring) fuzz against: plcrun's
// side of the HMI, the filling cell (fuzz_cell.hpp) in virtual time under a
// debugger, its HMI host in lockstep (served by round(), no thread) over
// memq://. The hmi: section publishes Cell.*, lets Cell.target_kg be written
// and Cell.run be forced; a target adds to it before the host is built.
#pragma once

#include <chrono>
#include <memory>
#include <utility>

#include "fuzz_cell.hpp"
#include "plc/debug/debugger.hpp"
#include "plc/hmi/host.hpp"

namespace plc::fuzz {

inline CellConfig filling_cell_with_hmi() {
  CellConfig cfg = filling_cell();
  cfg.hmi.present = true;
  cfg.hmi.url.value = "memq://";
  cfg.hmi.publish = {{"Cell.*", {}}};
  cfg.hmi.writable = {{"Cell.target_kg", {}}};
  cfg.hmi.forceable = {{"Cell.run", {}}};
  return cfg;
}

struct LockstepHmiHost {
  CellConfig cfg;
  std::unique_ptr<hmi::Host> host;
  std::unique_ptr<debug::Debugger> dbg;

  explicit LockstepHmiHost(CellConfig config) : cfg(std::move(config)) {
    hmi::Host::Options ho;
    ho.mode = hmi::Host::Mode::Lockstep;
    host = std::make_unique<hmi::Host>(cfg.hmi, cfg.file, ho);
    debug::Debugger::Options o;
    o.span = std::chrono::seconds(1);
    o.on_build = [this](Runtime& rt) { host->attach(rt); };
    dbg = std::make_unique<debug::Debugger>([this] { return std::make_unique<Runtime>(cfg); }, o);
    host->set_debugger(dbg.get());
  }
  // The callbacks above hold `this`.
  LockstepHmiHost(const LockstepHmiHost&) = delete;
  LockstepHmiHost& operator=(const LockstepHmiHost&) = delete;
};

}  // namespace plc::fuzz
