#include "plc/hmi/host.hpp"

#include <openssl/crypto.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/random.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>

#include "plc/hmi/command_auth.hpp"
#include "plc/hmi/host_privileges.hpp"
#include "plc/hmi/pattern.hpp"
#include "plc/hmi/tls_files.hpp"
#include "plc/hmi/utime.hpp"

namespace plc::hmi {

namespace {

VarType type_for(io::AddrSize s) {
  switch (s) {
    case io::AddrSize::Bit:
      return VarType::BOOL;
    case io::AddrSize::Byte:
      return VarType::BYTE;
    case io::AddrSize::Word:
      return VarType::WORD;
    case io::AddrSize::DWord:
      return VarType::DWORD;
    default:
      return VarType::LWORD;
  }
}

void copy_text(char* dst, std::size_t cap, const std::string& s) {
  const std::size_t n = std::min(cap - 1, s.size());
  std::memcpy(dst, s.data(), n);
  dst[n] = '\0';
}

// The reply's text (bounded; the bridge shows it as it is).
void set_text(ipc::ReplyRecord& r, const std::string& s) {
  copy_text(r.text, sizeof r.text, s);
  r.text_size = std::uint16_t(std::min(s.size(), sizeof r.text - 1));
}

std::uint64_t boot_epoch() {
  std::uint64_t e = 0;
  // Never 0: 0 means "no epoch" to a reader.
  while (e == 0)
    if (getrandom(&e, sizeof e, 0) != sizeof e)
      e = std::uint64_t(utime_now()) ^ std::uint64_t(getpid());
  return e;
}

}  // namespace

struct Host::Layout {
  const Runtime* rt = nullptr;
  std::shared_ptr<ipc::Regions> regions;  // the observers write into it
  ipc::CellLayout cell;
  std::map<std::string, std::uint32_t> index;  // path -> cell.vars
  std::vector<std::unique_ptr<ScanSnapshot>> snaps;
  std::uint64_t generation = 0;
};

Host::Host(const HmiConfig& cfg, std::string cell_file, Options options)
    : cfg_(cfg), cell_file_(std::move(cell_file)), opt_(std::move(options)) {
  copy_text(settings_.url, sizeof settings_.url, cfg_.url.value);
  copy_text(settings_.prefix, sizeof settings_.prefix, cfg_.prefix.value);
  copy_text(settings_.cell_file, sizeof settings_.cell_file, cell_file_);
  settings_.url_line = cfg_.url.mark.line;
  settings_.url_column = cfg_.url.mark.column;
  settings_.rate = cfg_.rate.value;
  settings_.stop_commands = cfg_.stop_commands.value ? 1 : 0;
  if (!cfg_.key_path.empty()) {
    std::string err;
    const auto key = load_key(cfg_.key_path, err);
    if (!key) throw ConfigError(cell_file_, cfg_.key_file.mark, "key 'key_file': " + err);
    settings_.has_key = 1;
    std::memcpy(settings_.key, key->data(), key->size());
  }
  if (cfg_.web.present) {
    const WebConfig& w = cfg_.web;
    settings_.web_port = std::uint16_t(w.port.value);
    settings_.web_read_only = w.read_only.value ? 1 : 0;
    copy_text(settings_.web_address, sizeof settings_.web_address, w.address.value);
    const std::string& login = w.login.value;
    settings_.web_login = std::uint8_t(login == "none"  ? ipc::WebLogin::None
                                       : login == "key" ? ipc::WebLogin::Key
                                                        : ipc::WebLogin::Hash);
    if (settings_.web_login == std::uint8_t(ipc::WebLogin::Hash))
      copy_text(settings_.web_password_hash, sizeof settings_.web_password_hash, login);
    if (w.tls) {
      TlsFilesError err;
      auto files = load_tls_files(w.tls_cert_path, w.tls_key_path, err);
      if (!files)
        throw ConfigError(cell_file_, err.in_key ? w.tls_key.mark : w.tls_cert.mark,
                          std::string(err.in_key ? "key 'key': " : "key 'cert': ") + err.message);
      if (!files->warning.empty()) log("web: tls: " + files->warning);
      // Both fit (load_tls_files' bounds are the fields' sizes less the NUL).
      copy_text(settings_.web_tls_cert, sizeof settings_.web_tls_cert, files->cert_pem);
      copy_text(settings_.web_tls_key, sizeof settings_.web_tls_key, files->key_pem);
      OPENSSL_cleanse(files->key_pem.data(), files->key_pem.size());
    }
  }
  boot_epoch_ = boot_epoch();
  if (opt_.mode != Mode::Lockstep) {
    doorbell_ = eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    if (doorbell_ < 0) throw std::system_error(errno, std::generic_category(), "eventfd");
  }
  if (opt_.mode == Mode::Supervised) privileges_ = resolve_privileges(cfg_, cell_file_);
}

Host::~Host() {
  stop();
  if (doorbell_ >= 0) close(doorbell_);
}

void Host::log(const std::string& line) const {
  if (opt_.log) {
    opt_.log(line);
    return;
  }
  std::fprintf(stderr, "plcrun: hmi: %s\n", line.c_str());
  std::fflush(stderr);
}

void Host::add_start_alarm(const std::string& kind, const std::string& source,
                           const std::string& text) {
  start_alarms_.push_back({kind, source, text, utime_now()});
}

void Host::attach(Runtime& rt) {
  auto l = std::make_shared<Layout>();
  l->rt = &rt;
  ipc::CellLayout& cell = l->cell;
  cell.cell = rt.cell_name();
  cell.layout_hash = rt.layout_hash();
  cell.image_input = std::uint32_t(rt.image().area(io::Area::Input).size());
  cell.image_output = std::uint32_t(rt.image().area(io::Area::Output).size());
  cell.image_memory = std::uint32_t(rt.image().area(io::Area::Memory).size());
  for (const auto& t : rt.tasks()) cell.tasks.push_back({t->name, t->period.count()});
  for (const DeviceRuntime& d : rt.devices())
    cell.devices.push_back({d.name, d.plugin_name, d.in.to_string(), d.out.to_string(), d.task,
                            std::int32_t(d.sizes.input_bytes), std::int32_t(d.sizes.output_bytes)});
  cell.start_alarms = start_alarms_;

  auto may = [](const std::vector<Item<std::string>>& patterns, const std::string& name) {
    for (const auto& p : patterns)
      if (pattern_matches(p.value, name)) return true;
    return false;
  };
  std::vector<bool> used(cfg_.publish.size() + cfg_.writable.size() + cfg_.forceable.size());
  auto note = [&](const std::string& name) {
    std::size_t k = 0;
    bool published = false;
    for (const auto* list : {&cfg_.publish, &cfg_.writable, &cfg_.forceable})
      for (const auto& p : *list) {
        const bool m = pattern_matches(p.value, name);
        if (m) used[k] = true;
        if (m && list == &cfg_.publish) published = true;
        ++k;
      }
    return published;
  };
  // The task whose scans see an address best: the one that exchanges its
  // device, else the fastest.
  auto task_of_address = [&rt](const io::IecAddress& a) {
    for (const DeviceRuntime& d : rt.devices()) {
      const io::IecAddress& base = a.area == io::Area::Input ? d.in : d.out;
      const std::size_t n = a.area == io::Area::Input ? d.sizes.input_bytes : d.sizes.output_bytes;
      if (a.area != io::Area::Memory && base.area == a.area && a.byte >= base.byte &&
          a.byte < base.byte + n && d.task >= 0)
        return d.task;
    }
    int best = 0;
    for (const auto& t : rt.tasks())
      if (t->period < rt.tasks()[std::size_t(best)]->period) best = int(t->order);
    return best;
  };
  std::vector<std::vector<ScanSnapshot::Item>> per_task(rt.tasks().size());
  auto add = [&](VarInfo v, bool published, bool read_only) {
    ipc::CellLayout::Var d;
    d.path = v.path;
    d.type = v.type;
    d.address = v.address;
    d.task = v.task;
    d.published = published && v.task >= 0;
    d.read_only = read_only;
    d.writable = !read_only && v.type != VarType::STRING && may(cfg_.writable, v.path);
    d.forceable = !read_only && v.type != VarType::STRING && may(cfg_.forceable, v.path);
    const int index = int(cell.vars.size());
    l->index[d.path] = std::uint32_t(index);
    cell.vars.push_back(d);
    if (d.published) per_task[std::size_t(v.task)].push_back({std::move(v), 0, index});
  };
  for (const VarInfo& v : rt.vars().all()) add(v, note(v.path), v.read_only);
  // Patterns that are IEC addresses publish the address itself.
  for (const auto* list : {&cfg_.publish, &cfg_.writable, &cfg_.forceable})
    for (const auto& p : *list) {
      if (p.value.empty() || p.value[0] != '%') continue;
      auto r = io::parse_iec_address(p.value);
      if (!r.address) throw ConfigError(cell_file_, p.mark, "hmi: '" + p.value + "': " + r.error);
      if (!rt.image().contains(*r.address))
        throw ConfigError(cell_file_, p.mark, "hmi: " + p.value + " lies outside the image");
      if (l->index.count(r.address->to_string())) continue;
      const int task = task_of_address(*r.address);
      VarInfo v;
      v.path = r.address->to_string();
      v.type = type_for(r.address->size);
      v.address = *r.address;
      v.order = rt.byte_order();
      v.task = task;
      // Read from the task's own copy of the image: consistent within its scan.
      v.image_ptr = rt.tasks()[std::size_t(task)]->image.at(*r.address);
      add(v, note(v.path), false);
    }
  std::size_t k = 0;
  for (const auto* list : {&cfg_.publish, &cfg_.writable, &cfg_.forceable})
    for (const auto& p : *list) {
      if (!used[k++])
        throw ConfigError(cell_file_, p.mark,
                          "hmi: pattern '" + p.value +
                              "' matches no variable (plcrun CONFIG --list-vars lists them)");
    }
  for (std::size_t t = 0; t < per_task.size(); ++t) {
    if (per_task[t].empty()) continue;
    if (cell.slots.size() == ipc::kMaxSlots)
      throw ConfigError(
          cell_file_, cfg_.mark,
          "hmi: published variables in more than " + std::to_string(ipc::kMaxSlots) + " tasks");
    auto s = std::make_unique<ScanSnapshot>(int(t), std::move(per_task[t]));
    ipc::CellLayout::Slot slot;
    slot.task = std::uint32_t(t);
    slot.buffer_size = s->buffer_size();
    for (const auto& it : s->items())
      slot.items.push_back({std::uint32_t(it.index), std::uint32_t(it.offset)});
    cell.slots.push_back(std::move(slot));
    l->snaps.push_back(std::move(s));
  }

  // The shared memory: the first build makes it; a rebuild of the same
  // shape (goto, restart) rewrites it in place; one of another shape (a
  // restart after an online change) needs new regions, and the bridge
  // process is started again on them.
  bool fresh = false;
  if (!regions_ || !regions_->fits(cell)) {
    regions_ = ipc::Regions::create(settings_, cell, boot_epoch_);
    fresh = true;
  } else {
    regions_->rewrite(cell);
  }
  l->regions = regions_;
  l->generation = regions_->state().generation.load(std::memory_order_acquire);
  for (std::size_t s = 0; s < l->snaps.size(); ++s)
    l->snaps[s]->bind(&regions_->slot_header(cell.slots[s]), regions_->slot_buffer(cell.slots[s]),
                      &regions_->control().requests[s]);
  for (std::size_t s = 0; s < l->snaps.size(); ++s) {
    ScanSnapshot* sp = l->snaps[s].get();
    const auto task = std::size_t(sp->task());
    // The observer keeps the layout (and the mapping) alive as long as the runtime.
    rt.add_scan_observer([sp, l, task](const TaskRuntime& tr, const ScanContext& ctx) {
      if (tr.order == task) sp->on_scan_end(tr, ctx);
    });
  }
  {
    std::lock_guard<std::mutex> lock(layout_mu_);
    const bool rebuilt = layout_ != nullptr;
    layout_ = l;
    if (fresh && rebuilt) {
      write_outages();
      if (supervisor_) restart_bridge_ = true;
      if (new_regions_) new_regions_();
    }
  }
}

// ---------------------------------------------------------------- rounds

int Host::round() {
  std::shared_ptr<Layout> l;
  {
    std::lock_guard<std::mutex> lock(layout_mu_);
    l = layout_;
  }
  if (!l) return 0;
  ipc::StateHeader& st = l->regions->state();
  ipc::Ring<ipc::CommandRecord> ring = l->regions->commands();
  ipc::Ring<ipc::ReplyRecord> replies = l->regions->replies();
  if (!rec_) rec_ = std::make_unique<ipc::CommandRecord>();
  if (!reply_) reply_ = std::make_unique<ipc::ReplyRecord>();
  int served = 0;
  for (std::uint32_t i = 0; i < ring.capacity(); ++i) {
    const auto got = ring.pop(*rec_);
    if (got == ipc::Ring<ipc::CommandRecord>::Pop::Empty) break;
    if (got == ipc::Ring<ipc::CommandRecord>::Pop::Skipped) {
      st.host.skipped.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    serve(*rec_, *l, *reply_);
    if (!replies.push(*reply_)) st.host.replies_lost.fetch_add(1, std::memory_order_relaxed);
    ++served;
  }
  const auto now = std::chrono::steady_clock::now();
  if (opt_.mode == Mode::Lockstep || now >= next_notes_) {
    refresh_notes(*l);
    next_notes_ = now + std::chrono::milliseconds(20);
  }
  return served;
}

template <class F>
bool Host::with_runtime(const Layout& l, F f) {
  if (!dbg_) {
    f(*const_cast<Runtime*>(l.rt));  // no debugger: nothing rebuilds it
    return true;
  }
  // The runtime may be rebuilt (goto): read it only between commands, and
  // skip this round when the console is running one.
  std::unique_lock<std::recursive_mutex> session(dbg_->session_mutex(), std::try_to_lock);
  if (!session.owns_lock() || &dbg_->runtime() != l.rt) return false;
  f(dbg_->runtime());
  return true;
}

void Host::serve(const ipc::CommandRecord& rec, const Layout& l, ipc::ReplyRecord& reply) {
  reply = ipc::ReplyRecord{};
  reply.token = rec.token;
  ipc::StateHeader& st = l.regions->state();
  const RecordCheck check = check_record(rec, l.cell, l.generation, cfg_.stop_commands.value);
  auto refuse = [&](ipc::Reason r, const std::string& why) {
    reply.reason = std::uint8_t(r);
    set_text(reply, why);
    st.host.refused.fetch_add(1, std::memory_order_relaxed);
    if (r == ipc::Reason::Malformed || r == ipc::Reason::Stale || r == ipc::Reason::BadOperand)
      st.host.malformed.fetch_add(1, std::memory_order_relaxed);
  };
  if (!check.command) return refuse(check.reason, check.why);
  if (!dbg_) return refuse(ipc::Reason::NoDebugger, "this cell serves no commands (no debugger)");
  // Up to 200 tries 1 ms apart rather than try_lock_for: a timed lock is
  // pthread_mutex_clocklock, which ThreadSanitizer does not intercept (it
  // then reports every unlock of the session mutex as a wrong-thread unlock).
  std::unique_lock<std::recursive_mutex> session(dbg_->session_mutex(), std::defer_lock);
  for (int i = 0; i < 200 && !session.try_lock(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (!session.owns_lock())
    return refuse(ipc::Reason::Busy, "busy: the debugger console is running a command");
  if (&dbg_->runtime() != l.rt) return refuse(ipc::Reason::Stale, "the cell was rebuilt meanwhile");
  st.host.served.fetch_add(1, std::memory_order_relaxed);
  execute(*check.command, l, reply);
  if (reply.reason != std::uint8_t(ipc::Reason::Ok))
    st.host.refused.fetch_add(1, std::memory_order_relaxed);
}

std::string Host::name_of(const Layout& l, const HostTarget& t) const {
  return t.var ? l.cell.vars[*t.var].path : t.address->to_string();
}

void Host::execute(const HostCommand& c, const Layout& l, ipc::ReplyRecord& reply) {
  using ipc::Verb;
  debug::Debugger::Reply d{false, ""};
  switch (c.verb) {
    case Verb::Read: {
      std::vector<std::string> names;
      for (const HostTarget& t : c.operands) names.push_back(name_of(l, t));
      const auto values = dbg_->read_typed(names);
      for (std::size_t i = 0; i < values.size() && i < ipc::kMaxReadOperands; ++i) {
        const auto& v = values[i];
        ipc::WireValue& w = reply.values[i];
        const std::string err = !v.error.empty() ? v.error : v.no_value;
        w.has_value = err.empty() ? 1 : 0;
        w.type = std::uint8_t(v.type);
        w.forced = v.forced ? 1 : 0;
        w.image_differs = v.image_differs ? 1 : 0;
        std::memcpy(w.bytes, v.bytes, sizeof v.bytes);
        std::memcpy(w.image, v.image, sizeof w.image);
        copy_text(w.error, sizeof w.error, err);
      }
      reply.n_values = std::uint8_t(std::min(values.size(), ipc::kMaxReadOperands));
      d = {true, ""};
      break;
    }
    case Verb::Write:
      d = dbg_->write_raw(name_of(l, c.target), c.value);
      break;
    case Verb::Force:
      d = dbg_->force_raw(name_of(l, c.target), c.value);
      break;
    case Verb::Unforce:
      d = dbg_->unforce(name_of(l, c.target), c.restore);
      break;
    case Verb::UnforceAll: {
      // Only what the HMI may force, in one step of the debugger (no scan
      // sees some released and others not): a force the console set on
      // anything else stays, value and all.
      std::string kept;
      d = dbg_->unforce_if(
          [&](const std::string& name) {
            const auto it = l.index.find(name);
            if (it != l.index.end() && l.cell.vars[it->second].forceable) return true;
            kept += "kept " + name + " (the cell's hmi: forceable patterns do not match it)\n";
            return false;
          },
          c.restore);
      if (d.ok)
        d.text += kept;
      else
        d.text = "unforce all: no force that this client may release\n" + kept;
      break;
    }
    case Verb::Pause:
      d = dbg_->pause();
      break;
    case Verb::Step:
      d = dbg_->step(c.count);
      break;
    case Verb::Continue:
      d = dbg_->continue_running();
      break;
    case Verb::Break: {
      std::vector<debug::ConditionOperand> ops;
      for (const HostTarget& t : c.operands)
        ops.push_back(t.var ? debug::ConditionOperand{l.cell.vars[*t.var].path, std::nullopt}
                            : debug::ConditionOperand{"", t.address});
      d = dbg_->add_breakpoint(c.code, std::move(ops), c.count);
      if (!d.ok) {
        reply.reason = std::uint8_t(ipc::Reason::BadCode);
        set_text(reply, d.text);
        return;
      }
      break;
    }
    case Verb::Delete:
      d = dbg_->delete_breakpoint(std::to_string(c.count));
      break;
    case Verb::DeleteAll:
      d = dbg_->delete_breakpoint("all");
      break;
    default:
      d = {false, "unknown verb"};
  }
  reply.reason = std::uint8_t(d.ok ? ipc::Reason::Ok : ipc::Reason::Refused);
  set_text(reply, d.text);
}

void Host::refresh_notes(const Layout& l) {
  ipc::StatsNote stats;
  ipc::DiagNote diag;
  const bool read = with_runtime(l, [&](Runtime& rt) {
    for (const auto& t : rt.tasks()) {
      const TaskStats s = t->stats.snapshot();
      ipc::StatsNote::Task n;
      n.scans = s.scans;
      n.overruns = s.overruns;
      n.skipped = s.skipped;
      n.scan_ns_min = std::int64_t(s.scan_ns.min());
      n.scan_ns_avg = std::int64_t(s.scan_ns.mean());
      n.scan_ns_max = std::int64_t(s.scan_ns.max());
      n.stop_reason = s.stop_reason.substr(0, ipc::kMaxStopReason);
      stats.tasks.push_back(std::move(n));
    }
    for (const DeviceRuntime& d : rt.devices()) {
      const io::DeviceLink& link = d.plugin->link(d.index);
      const io::DeviceLink::StateChange c = link.last_change();
      ipc::DiagNote::Device n;
      n.live_state = std::uint8_t(link.live_state());
      n.seen_state = std::uint8_t(link.state());
      n.changes = c.count;
      n.from = std::uint8_t(c.from);
      n.to = std::uint8_t(c.to);
      n.torn = c.torn;
      n.scan = c.scan;
      n.time_ns = c.time.count();
      n.diagnostics = d.plugin->diagnostics(d.index).substr(0, ipc::kMaxDiagnosticsText);
      diag.devices.push_back(std::move(n));
    }
  });
  if (!read) return;
  l.regions->stats().write(stats.encode());
  l.regions->diag().write(diag.encode());
}

// ---------------------------------------------------------------- outages

void Host::write_outages() {
  if (!regions_) return;
  regions_->outages().write(outages_.encode());
}

void Host::note_outage(const std::string& cause, std::int64_t down_utime) {
  std::lock_guard<std::mutex> lock(outages_mu_);
  ipc::OutageNote::Outage o;
  o.number = ++outages_.total;
  o.cause = cause.substr(0, 200);
  o.down_utime = down_utime;
  outages_.recent.push_back(o);
  if (outages_.recent.size() > ipc::OutageNote::kKept)
    outages_.recent.erase(outages_.recent.begin());
  down_total_us_ -= down_utime;
  write_outages();
}

// ---------------------------------------------------------------- thread

void Host::start() {
  if (opt_.mode == Mode::Lockstep || thread_.joinable() || !regions_) return;
  stop_ = false;
  if (opt_.mode == Mode::Supervised) make_supervisor();
  thread_ = std::thread([this] { run(); });
}

void Host::make_supervisor() {
  Supervisor::Spawn s;
  s.exe = opt_.plchmi.empty() ? default_plchmi_path() : opt_.plchmi;
  s.args = {"--state-fd", "3", "--control-fd", "4", "--doorbell-fd", "5"};
  s.fds = {regions_->state_fd(), regions_->control_fd(), doorbell_};
  s.netns_fd = privileges_.netns_fd;
  s.change_user = privileges_.change_user;
  s.uid = privileges_.uid;
  s.gid = privileges_.gid;
  supervisor_ = std::make_unique<Supervisor>(s, opt_.backoff);
}

void Host::run() {
  using Clock = std::chrono::steady_clock;
  while (!stop_.load()) {
    if (restart_bridge_.exchange(false) && supervisor_) {
      // New regions: plchmi starts again on them (not an outage).
      supervisor_->stop();
      make_supervisor();
      log("cell layout changed: plchmi restarted on the new layout");
    }
    int timeout_ms = 20;
    if (supervisor_)
      if (auto due = supervisor_->next_start()) {
        const auto ms =
            std::chrono::duration_cast<std::chrono::milliseconds>(*due - Clock::now()).count();
        timeout_ms = int(std::clamp<std::int64_t>(ms, 0, 20));
      }
    pollfd fds[2] = {{doorbell_, POLLIN, 0}, {supervisor_ ? supervisor_->pidfd() : -1, POLLIN, 0}};
    ::poll(fds, 2, timeout_ms);
    if (fds[0].revents & POLLIN) {
      std::uint64_t n = 0;
      (void)!read(doorbell_, &n, sizeof n);  // nonblocking: the count is of no interest
    }
    round();
    if (supervisor_) supervise(Clock::now());
  }
}

void Host::supervise(std::chrono::steady_clock::time_point now) {
  for (const Supervisor::Event& e : supervisor_->poll(now)) {
    const double restart_s = std::chrono::duration<double>(e.restart_in).count();
    char b[64];
    std::snprintf(b, sizeof b, "%.1f s", restart_s);
    switch (e.kind) {
      case Supervisor::Event::Kind::Exited:
        note_outage("plchmi " + e.text, utime_now());
        log("plchmi " + e.text + "; restart in " + b);
        break;
      case Supervisor::Event::Kind::StartFailed:
        log("plchmi could not be started: " + e.text + "; next try in " + b);
        break;
      case Supervisor::Event::Kind::Started: {
        std::lock_guard<std::mutex> lock(outages_mu_);
        if (!outages_.recent.empty() && outages_.recent.back().up_utime == 0) {
          const std::int64_t now_us = utime_now();
          const double down = double(now_us - outages_.recent.back().down_utime) / 1e6;
          std::snprintf(b, sizeof b, "%.2f s", down);
          outages_.recent.back().up_utime = now_us;
          down_total_us_ += now_us;
          write_outages();
          log("plchmi back (pid " + std::to_string(supervisor_->pid()) + ") after " + b);
        } else {
          log("plchmi started (pid " + std::to_string(supervisor_->pid()) + ")");
        }
        break;
      }
    }
  }
}

void Host::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
  if (supervisor_) supervisor_->stop();
}

int Host::bridge_pid() const { return supervisor_ ? int(supervisor_->pid()) : 0; }

std::vector<std::string> Host::summary() const {
  std::vector<std::string> out;
  if (!regions_) return out;
  {
    std::lock_guard<std::mutex> lock(outages_mu_);
    if (supervisor_) {
      std::int64_t down = down_total_us_;
      if (!outages_.recent.empty() && outages_.recent.back().up_utime == 0) down += utime_now();
      char b[64];
      std::snprintf(b, sizeof b, "%.2f s", double(down) / 1e6);
      std::string s = "plchmi started " + std::to_string(supervisor_->starts()) + " time(s), " +
                      std::to_string(outages_.total) + " outage(s), down " + b + " in total";
      if (!outages_.recent.empty()) s += "; last: " + outages_.recent.back().cause;
      out.push_back(s);
    }
  }
  const ipc::BridgeCounters& c = regions_->control().bridge;
  const ipc::HostCounters& h = regions_->state().host;
  auto n = [](const std::atomic<std::uint64_t>& a) { return std::to_string(a.load()); };
  out.push_back("bridge: published " + n(c.published) + ", commands " + n(c.commands) +
                ", refused " + n(c.refused) + ", bad tag " + n(c.bad_tag) + ", replayed " +
                n(c.replayed) + ", stale " + n(c.stale) + ", malformed " + n(c.malformed) +
                " (as plchmi counted)");
  out.push_back("host: " + n(h.served) + " command(s) served, " + n(h.refused) +
                " refused by plcrun (" + n(h.malformed) + " malformed), " + n(h.skipped) +
                " ring resets, " + n(h.replies_lost) + " replies lost");
  return out;
}

}  // namespace plc::hmi
