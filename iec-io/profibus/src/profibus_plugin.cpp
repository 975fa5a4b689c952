#include "plc/profibus/profibus_plugin.hpp"

#include <poll.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "plc/config_path.hpp"
#include "plc/profibus/dp/cfg.hpp"
#include "plc/profibus/gsd/gsd.hpp"
#include "plc/profibus/slave/from_gsd.hpp"
#include "plc/realtime_thread.hpp"

namespace plc::profibus {

namespace {
using std::chrono::milliseconds;
using std::chrono::seconds;

// The device keys the plugin reads; every other key goes to the device
// model (simulate: true).
const char* const kDeviceKeys[] = {"address", "gsd",      "modules",  "cfg",    "ident", "watchdog",
                                   "group",   "min_tsdr", "user_prm", "freeze", "sync",  "active"};

std::vector<std::uint8_t> hex_bytes(const std::string& s, const char* key) {
  std::vector<std::uint8_t> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == ',')) ++i;
    if (i >= s.size()) break;
    std::size_t j = i;
    while (j < s.size() && s[j] != ' ' && s[j] != ',') ++j;
    std::string tok = s.substr(i, j - i);
    if (tok.rfind("0x", 0) == 0 || tok.rfind("0X", 0) == 0) tok = tok.substr(2);
    char* end = nullptr;
    const unsigned long v = std::strtoul(tok.c_str(), &end, 16);
    if (tok.empty() || tok.size() > 2 || *end != '\0' || v > 255)
      throw io::ParamError(key, std::string(key) + ": '" + s.substr(i, j - i) +
                                    "' is not a hex byte (e.g. \"B7 FF\")");
    out.push_back(static_cast<std::uint8_t>(v));
    i = j;
  }
  return out;
}
}  // namespace

ProfibusPlugin::ProfibusPlugin() = default;
ProfibusPlugin::~ProfibusPlugin() { stop(); }

void ProfibusPlugin::configure(const io::ModelParams& p) {
  baud_ = static_cast<std::uint32_t>(p.get_int("baud", 1500000, 9600, 12000000));
  if (!fdl::baud_profile(baud_))
    throw io::ParamError("baud",
                         "baud must be one of 9600, 19200, 45450, 93750, 187500, 500000, 1500000, "
                         "3000000, 6000000, 12000000");
  cfg_.address = static_cast<std::uint8_t>(p.get_int("address", 1, 0, 125));
  simulate_ = p.get_bool("simulate", false);
  transport_ = p.get_string("transport", "");
  // The device path of serial:/pty: is a file named by the config: a
  // relative one is taken from the config file's folder, as gsd:, capture:
  // and pcap: are (plc/config_path.hpp).
  for (const char* kind : {"serial:", "pty:"})
    if (transport_.rfind(kind, 0) == 0 && transport_.size() > std::strlen(kind))
      transport_ = kind + plc::path_in_folder(p.folder().empty() ? "." : p.folder(),
                                              transport_.substr(std::strlen(kind)));
  if (simulate_ && !transport_.empty())
    throw io::ParamError("transport",
                         "simulate: true runs on an in-memory line: leave transport out");
  if (!simulate_ && transport_.rfind("serial:", 0) != 0 && transport_.rfind("pty:", 0) != 0)
    throw io::ParamError(transport_.empty() ? "" : "transport",
                         "the profibus plugin needs transport: serial:DEVICE or pty:PATH (or "
                         "simulate: true)");
  cycle_given_ = p.has("cycle");
  cfg_.cycle = p.get_time("cycle", milliseconds(5), TIME(0), seconds(10));
  timeout_given_ = p.has("reply_timeout");
  cfg_.min_reply_timeout =
      p.get_time("reply_timeout", simulate_ ? TIME(0) : milliseconds(20), TIME(0), seconds(10));
  retry_limit_given_ = p.has("max_retry");
  retry_limit_ = static_cast<std::uint8_t>(p.get_int("max_retry", 1, 0, 15));
  cfg_.retry = p.get_time("retry", seconds(1), milliseconds(10), seconds(600));
  cfg_.bus.gap_factor = static_cast<std::uint8_t>(p.get_int("gap_factor", 10, 0, 100));
  cfg_.bus.hsa = static_cast<std::uint8_t>(p.get_int("hsa", 126, 2, 126));
  if (cfg_.address > cfg_.bus.hsa)
    throw io::ParamError("address", "the master's address is above hsa");
  cfg_.token = p.get_bool("token", true);
  capture_path_ = p.get_path("capture");
  pcap_path_ = p.get_path("pcap");
  log_ = p.get_bool("log", true);
  priority_ = static_cast<int>(p.get_int("priority", 60, 1, 99));
  p.reject_unknown();
}

io::DeviceSizes ProfibusPlugin::add_device(const io::DeviceSpec& spec) {
  const io::ModelParams& p = spec.params;
  Entry e;
  e.name = spec.name;
  master::SlaveEntry& s = e.slave;
  s.name = spec.name;
  if (!p.has("address"))
    throw io::ParamError("address", "every PROFIBUS device needs its address (0..125)");
  s.address = static_cast<std::uint8_t>(p.get_int("address", 0, 0, 125));
  if (s.address == cfg_.address)
    throw io::ParamError("address", "the device has the master's address");
  for (const Entry& o : entries_)
    if (o.slave.address == s.address)
      throw io::ParamError("address", "address " + std::to_string(s.address) +
                                          " is already used by '" + o.name + "'");
  // The GSD: identity, modules, MaxTsdr, Min_Slave_Intervall, user parameters.
  std::optional<gsd::Gsd> g;
  if (p.has("gsd")) {
    try {
      g = gsd::load_gsd(p.get_path("gsd"));  // relative: from the config file's folder
    } catch (const gsd::GsdError& err) {
      throw io::ParamError("gsd", err.what());
    }
  }
  const fdl::BaudProfile* prof = fdl::baud_profile(baud_);
  std::vector<const gsd::Module*> chosen;
  if (p.has("modules")) {
    if (!g) throw io::ParamError("modules", "modules: by name needs gsd: FILE");
    const std::string list = p.get_string("modules", "");
    std::size_t pos = 0;
    while (pos <= list.size()) {
      const std::size_t semi = list.find(';', pos);
      std::string name =
          list.substr(pos, semi == std::string::npos ? std::string::npos : semi - pos);
      name.erase(0, name.find_first_not_of(' '));
      name.erase(name.find_last_not_of(' ') + 1);
      if (!name.empty()) {
        const gsd::Module* m = g->module(name);
        if (!m) {
          std::string known;
          for (const auto& x : g->modules) known += (known.empty() ? "" : ", ") + x.name;
          throw io::ParamError(
              "modules", "no module '" + name + "' in " + g->file + " (modules: " + known + ")");
        }
        chosen.push_back(m);
        s.cfg.insert(s.cfg.end(), m->cfg.begin(), m->cfg.end());
      }
      if (semi == std::string::npos) break;
      pos = semi + 1;
    }
    if (chosen.empty()) throw io::ParamError("modules", "modules: at least one module name");
    if (g->modular() && chosen.size() > g->max_modules())
      throw io::ParamError("modules", std::to_string(chosen.size()) +
                                          " modules, the GSD's Max_Module is " +
                                          std::to_string(g->max_modules()));
  }
  if (p.has("cfg")) {
    if (!s.cfg.empty()) throw io::ParamError("cfg", "give modules or cfg, not both");
    s.cfg = hex_bytes(p.get_string("cfg", ""), "cfg");
  }
  if (s.cfg.empty())
    throw io::ParamError("modules",
                         "the device needs modules: (names from its GSD) or cfg: (bytes)");
  const auto sizes = dp::cfg_sizes(s.cfg);
  if (!sizes) throw io::ParamError("cfg", "malformed configuration " + dp::hex(s.cfg));
  s.input_bytes = sizes->input_bytes;
  s.output_bytes = sizes->output_bytes;
  if (s.input_bytes > 244 || s.output_bytes > 244)
    throw io::ParamError("cfg", "more than 244 bytes one way do not fit a Data_Exchange telegram");
  if (g) {
    s.prm.ident = g->ident();
    if (!g->baud_supported(prof->gsd_suffix))
      throw io::ParamError("gsd", g->file + " does not list " + prof->gsd_suffix + "_supp = 1");
    e.gsd_max_tsdr = g->max_tsdr(prof->gsd_suffix).value_or(0);
    e.min_interval_us = g->min_slave_interval() * 100;
    try {
      s.prm.user = g->user_prm_data(chosen);
    } catch (const gsd::GsdError& err) {
      throw io::ParamError("gsd", err.what());
    }
  }
  if (p.has("ident")) s.prm.ident = static_cast<std::uint16_t>(p.get_int("ident", 0, 0, 0xFFFF));
  if (!g && !p.has("ident"))
    throw io::ParamError("ident", "without gsd: the device needs its ident");
  if (p.has("user_prm")) s.prm.user = hex_bytes(p.get_string("user_prm", ""), "user_prm");
  if (s.prm.user.size() > 237) throw io::ParamError("user_prm", "at most 237 user parameter bytes");
  const TIME wd = p.get_time("watchdog", milliseconds(200), TIME(0), milliseconds(650250));
  const auto wd_ms =
      static_cast<std::uint32_t>(std::chrono::duration_cast<milliseconds>(wd).count());
  s.prm.station_status = dp::kPrmLockReq;
  if (wd_ms > 0) {
    s.prm.station_status |= dp::kPrmWdOn;
    const auto [f1, f2] = dp::watchdog_factors(wd_ms);
    s.prm.wd_fact1 = f1;
    s.prm.wd_fact2 = f2;
  }
  const std::int64_t group = p.get_int("group", 0, 0, 8);
  s.prm.group = group == 0 ? 0 : static_cast<std::uint8_t>(1u << (group - 1));
  s.prm.min_tsdr = static_cast<std::uint8_t>(p.get_int("min_tsdr", 11, 0, 255));
  const bool freeze = p.get_bool("freeze", false), sync = p.get_bool("sync", false);
  if (freeze && g && !g->freeze_supported())
    throw io::ParamError("freeze", "the GSD says Freeze_Mode_supp = 0");
  if (sync && g && !g->sync_supported())
    throw io::ParamError("sync", "the GSD says Sync_Mode_supp = 0");
  if (freeze) s.prm.station_status |= dp::kPrmFreezeReq;
  if (sync) s.prm.station_status |= dp::kPrmSyncReq;
  s.active = p.get_bool("active", true);

  // The device model: simulated behind a DP slave (simulate: true); its
  // window must fit the configured I/O.
  io::ModelParams model_params;
  model_params.set_folder(p.folder());
  for (const auto& [k, v] : p.values()) {
    bool ours = false;
    for (const char* c : kDeviceKeys) ours = ours || k == c;
    if (!ours) model_params.set(k, v);
  }
  if (const auto* f = io::DeviceModelRegistry::instance().find(spec.model)) {
    e.model = (*f)(model_params);
    if (e.model->input_size() > s.input_bytes || e.model->output_size() > s.output_bytes)
      throw io::ParamError("", "the model's window (" + std::to_string(e.model->input_size()) +
                                   " in, " + std::to_string(e.model->output_size()) +
                                   " out) does not fit the configured I/O (" +
                                   std::to_string(s.input_bytes) + " in, " +
                                   std::to_string(s.output_bytes) + " out)");
  } else if (simulate_) {
    throw io::ParamError("model",
                         "simulate: true needs a device model, and '" + spec.model + "' is none");
  } else if (spec.model != "generic") {
    throw io::ParamError("model",
                         "profibus device model must be a registered device model (simulate) or "
                         "generic, not '" +
                             spec.model + "'");
  } else {
    model_params.reject_unknown();
  }
  if (!simulate_) e.model.reset();
  if (simulate_) {
    if (g) {
      e.sim = slave::slave_config_from_gsd(*g, s.address, s.input_bytes, s.output_bytes);
    } else {
      e.sim.address = s.address;
      e.sim.ident = s.prm.ident;
      e.sim.input_bytes = s.input_bytes;
      e.sim.output_bytes = s.output_bytes;
      e.sim.cfg = s.cfg;
      e.sim.user_prm_len = s.prm.user.size();
    }
  }
  // The master exists from the first device on: the runtime binds the
  // device's link right after add_device().
  if (!master_) master_ = std::make_unique<master::DpMaster>(cfg_, nullptr);
  master_->add(s);
  entries_.push_back(std::move(e));
  return {entries_.back().slave.input_bytes, entries_.back().slave.output_bytes};
}

void ProfibusPlugin::open() {
  if (line_) return;
  if (!master_) master_ = std::make_unique<master::DpMaster>(cfg_, nullptr);
  // Bus parameters from the baud rate and the slaves' GSDs; the bus cycle
  // is at least every slave's Min_Slave_Intervall.
  std::vector<std::uint32_t> tsdr;
  std::size_t io = 0;
  std::uint32_t min_interval_us = 0;
  for (const Entry& e : entries_) {
    if (e.gsd_max_tsdr) tsdr.push_back(e.gsd_max_tsdr);
    io = std::max({io, e.slave.input_bytes, e.slave.output_bytes});
    min_interval_us = std::max(min_interval_us, e.min_interval_us);
  }
  const std::uint8_t gap = cfg_.bus.gap_factor, hsa = cfg_.bus.hsa;
  cfg_.bus = fdl::bus_parameters(baud_, tsdr, entries_.size(), io);
  cfg_.bus.gap_factor = gap;
  cfg_.bus.hsa = hsa;
  if (retry_limit_given_) cfg_.bus.max_retry = retry_limit_;
  if (!cycle_given_)
    cfg_.cycle = std::max<TIME>(std::chrono::microseconds(min_interval_us), milliseconds(1));
  try {
    if (simulate_) {
      mem_ = link::MemBus::create();
      line_ = mem_->attach();
      for (Entry& e : entries_) {
        sim_lines_.push_back(mem_->attach());
        sim_.push_back(
            std::make_unique<slave::DpSlave>(e.sim, std::move(e.model), *sim_lines_.back()));
      }
    } else {
      line_ = link::open_line(transport_, baud_);
    }
    if (!capture_path_.empty() || !pcap_path_.empty())
      capture_ = std::make_unique<link::Capture>(capture_path_, pcap_path_);
  } catch (const std::exception& e) {
    throw io::PluginStartError(std::string("profibus: ") + e.what());
  }
  master_->configure(cfg_);
  master_->attach(line_.get());
  master_->set_capture(capture_.get());
  master_->on_change = [this](std::size_t d, master::SlaveState st, const std::string& why) {
    if (!log_) return;
    std::fprintf(stderr, "profibus: %s (address %u): %s%s%s\n", entries_[d].name.c_str(),
                 entries_[d].slave.address,
                 st == master::SlaveState::Online    ? "data exchange"
                 : st == master::SlaveState::Fault   ? "fault"
                 : st == master::SlaveState::Waiting ? "lost"
                                                     : "not ready",
                 why.empty() ? "" : ": ", why.c_str());
  };
  master_->on_other_master = [this](std::uint8_t a) {
    if (log_)
      std::fprintf(stderr,
                   "profibus: another master answers at address %u (multi-master is not "
                   "supported: this master keeps the token)\n",
                   a);
  };
  if (log_) {
    std::fprintf(stderr, "profibus: master %u on %s, %s; bus cycle %lld us\n", cfg_.address,
                 line_->describe().c_str(), cfg_.bus.describe().c_str(),
                 static_cast<long long>(cfg_.cycle.count() / 1000));
    for (const Entry& e : entries_)
      if (!e.slave.active)
        std::fprintf(stderr, "profibus: %s (address %u): deactivated (active: false)\n",
                     e.name.c_str(), e.slave.address);
  }
}

void ProfibusPlugin::start(io::ClockMode mode) {
  open();
  mode_ = mode;
  if (mode == io::ClockMode::RealTime && !running_.exchange(true))
    thread_ = std::thread([this] { run_realtime(); });
}

void ProfibusPlugin::stop() {
  if (running_.exchange(false) && thread_.joinable()) thread_.join();
  if (capture_) capture_->flush();
}

void ProfibusPlugin::serve_records() {
  for (std::size_t d = 0; d < entries_.size(); ++d) {
    io::DeviceLink& l = master_->link(d);
    for (io::RecordRequest* r = l.pop(); r; r = l.pop()) {
      if (r->kind() == io::RecordKind::Write && r->index() == kGlobalControlRecord &&
          r->data().size() == 2) {
        master_->global_control(r->data()[0], r->data()[1]);
        r->complete(0);
      } else {
        r->fail(io::RecordError::InvalidIndex);
      }
    }
  }
}

void ProfibusPlugin::tick(TIME now) {
  std::lock_guard<std::mutex> lock(mutex_);
  serve_records();
  master_->tick(now);
  if (sim_.empty()) return;
  // Simulated slaves: they answer at once, the master takes the answer and
  // sends the next request, until the bus cycle is done (or a slave keeps
  // silent and the master waits for its slot time).
  for (int i = 0; i < 8 * static_cast<int>(sim_.size()) + 16; ++i) {
    const auto before = master_->telegrams_sent();
    for (auto& s : sim_) s->tick(now);
    master_->tick(now);
    if (master_->telegrams_sent() == before) break;
  }
}

void ProfibusPlugin::step(TIME now, TIME) {
  if (master_) tick(now);
}

void ProfibusPlugin::run_realtime() {
  if (const int rc = set_fifo_priority(priority_); rc != 0 && log_)
    warn_fifo_refused("profibus", rc, "the bus thread runs at normal priority");
  const std::int64_t t0 = mono_ns();
  while (running_.load(std::memory_order_relaxed)) {
    tick(TIME(mono_ns() - t0));
    // Wake on the next bytes (an answer), or after at most 1 ms for the
    // timers (slot time, bus cycle); the in-memory line has no descriptor.
    const int fd = line_->fd();
    const std::int64_t before = mono_ns();
    if (fd >= 0) {
      pollfd pfd{fd, POLLIN, 0};
      (void)poll(&pfd, 1, 1);
      if (pfd.revents & (POLLHUP | POLLERR)) {
        timespec ts{0, 1'000'000};
        nanosleep(&ts, nullptr);
      }
    } else {
      timespec ts{0, 1'000'000};
      nanosleep(&ts, nullptr);
    }
    std::lock_guard<std::mutex> lock(mutex_);
    const std::int64_t late = mono_ns() - before - 1'000'000;
    ++wake_.wakes;
    if (late > 0) {
      wake_.sum_late_ns += late;
      wake_.max_late_ns = std::max(wake_.max_late_ns, late);
    }
  }
}

void ProfibusPlugin::latch_inputs(std::size_t device, std::span<std::uint8_t> dst) {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto src = master_->inputs(device);
  std::memcpy(dst.data(), src.data(), std::min(src.size(), dst.size()));
}

void ProfibusPlugin::publish_outputs(std::size_t device, std::span<const std::uint8_t> src) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto dst = master_->outputs(device);
  std::memcpy(dst.data(), src.data(), std::min(src.size(), dst.size()));
}

slave::DpSlave* ProfibusPlugin::simulated(std::size_t device) {
  return device < sim_.size() ? sim_[device].get() : nullptr;
}

std::string ProfibusPlugin::diagnostics(std::size_t device) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!line_) return "profibus: not started";
  std::string s = master_->diagnostics(device);
  const auto& c = line_->counters();
  const auto& m = master_->counters();
  char b[256];
  std::snprintf(
      b, sizeof b,
      "; line tx %llu rx-bytes %llu tx-dropped %llu bad-bytes %llu unexpected %llu "
      "late-answers %llu cycles %llu",
      static_cast<unsigned long long>(c.tx_telegrams), static_cast<unsigned long long>(c.rx_bytes),
      static_cast<unsigned long long>(c.tx_dropped), static_cast<unsigned long long>(m.bad_bytes),
      static_cast<unsigned long long>(m.unexpected),
      static_cast<unsigned long long>(m.late_answers), static_cast<unsigned long long>(m.cycles));
  s += b;
  return s;
}

PLC_REGISTER_PLUGIN("profibus", ProfibusPlugin)

}  // namespace plc::profibus
