#include "plc/debug/debugger.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "plc/debug/one_task.hpp"
#include "plc/iec_literal.hpp"
#include "plc/retain/retain_layout.hpp"
#include "plc/thread_guard.hpp"

namespace plc::debug {
namespace {

std::vector<std::string> words(std::string_view s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (std::isspace(static_cast<unsigned char>(c)) || c == ',') {
      if (!cur.empty()) out.push_back(std::move(cur));
      cur.clear();
    } else {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(std::move(cur));
  return out;
}

// The text after the first `n` words (conditions keep their spaces).
std::string rest_after(std::string_view line, std::size_t n) {
  std::size_t i = 0;
  for (std::size_t w = 0; w < n; ++w) {
    while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
    while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;
  }
  while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
  std::string r(line.substr(i));
  while (!r.empty() && std::isspace(static_cast<unsigned char>(r.back()))) r.pop_back();
  return r;
}

std::string seconds(TIME t) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6fs", std::chrono::duration<double>(t).count());
  return b;
}

std::optional<std::uint64_t> count_arg(const std::string& s) {
  auto v = parse_iec_unsigned(s);
  if (!v || *v == 0) return std::nullopt;
  return *v;
}

VarType type_for(io::AddrSize s) {
  static const VarType types[] = {VarType::BOOL, VarType::BYTE, VarType::WORD, VarType::DWORD,
                                  VarType::LWORD};
  return types[static_cast<int>(s)];
}

}  // namespace

Debugger::Debugger(Factory factory, Options options)
    : factory_(std::move(factory)), opt_(std::move(options)) {
  build();
}

Debugger::~Debugger() { detach(); }

void Debugger::stop_cell() {
  if (!rt_) return;
  if (rt_thread_.joinable()) {
    rt_->request_stop();
    rt_->set_paused(false);
    rt_thread_.join();  // run() ends with finish()
  } else if (opt_.mode == io::ClockMode::Virtual) {
    rt_->finish();
  }
}

void Debugger::detach() {
  if (!rt_) return;
  if (rt_thread_.joinable()) stop_cell();
  if (trace_) trace_->stop();
  recorder_.reset();
  replayer_.reset();
  rt_->remove_hooks(this);
  if (opt_.mode == io::ClockMode::Virtual) rt_->finish();
  rt_.reset();
}

std::unique_ptr<Trace> Debugger::make_trace(const VarRegistry& vars) const {
  auto trace = std::make_unique<Trace>(vars, rt_->image(), rt_->byte_order());
  trace->set_backpressure(opt_.mode == io::ClockMode::Virtual);
  if (opt_.mode == io::ClockMode::RealTime) {
    std::vector<std::string> names;
    for (const auto& t : rt_->tasks()) names.push_back(t->name);
    trace->set_one_task(std::move(names));
  }
  for (const std::string& spec : trace_spec_) {  // "add NAME", "trigger COND", "pre N"
    auto w = words(spec);
    if (w[0] == "add")
      trace->add(w[1]);
    else if (w[0] == "trigger")
      trace->set_trigger(rest_after(spec, 1));
    else if (w[0] == "pre")
      trace->set_pretrigger(std::stoul(w[1]));
  }
  return trace;
}

void Debugger::build(const std::function<void(Runtime&)>& before_start) {
  detach();
  rt_ = factory_();
  if (before_start) before_start(*rt_);
  if (opt_.on_build) opt_.on_build(*rt_);
  if (!opt_.replay_file.empty()) replayer_ = std::make_unique<Replayer>(*rt_, opt_.replay_file);
  rt_->add_hooks(this);
  rt_->add_scan_observer(
      [this](const TaskRuntime& t, const ScanContext& ctx) { on_scan_end(t, ctx); });
  {
    std::lock_guard<std::mutex> lock(mu_);
    last_ = {};
  }
  // Re-resolve everything that points into the old runtime.
  std::string err;
  for (Breakpoint& b : breaks_) {
    b.hits = 0;
    // By its operands' paths and addresses: a condition that came as code
    // (the HMI) is never parsed from text.
    if (b.cond) b.cond = b.cond->rebind(rt_->vars(), rt_->image(), rt_->byte_order(), err);
  }
  for (Force& f : forces_) {
    bool image = false;
    if (auto v = resolve(f.name, image, err)) f.var = *v;
  }
  writes_.clear();
  trace_ = make_trace(rt_->vars());
  {
    std::lock_guard<std::mutex> lock(mu_);
    note_scan_end_reads();
  }
  if (!opt_.record_file.empty()) {
    recorder_ = std::make_unique<Recorder>(*rt_, opt_.record_file, Recorder::Attach::ByCaller);
    recorder_->arm();
    opt_.record_file.clear();  // once: a later goto back stops it like any recording
  }
  if (opt_.mode == io::ClockMode::Virtual) {
    rt_->start(io::ClockMode::Virtual);
  } else {
    // Started here, before the thread: the mode and the image lock are set
    // before any command can look at them (and a plugin that fails to start
    // is an error of this call, not an exception on another thread).
    rt_->start(io::ClockMode::RealTime);
    // Should the run itself throw, the cell stops with every output safe.
    rt_thread_ = std::thread([this] {
      run_guarded(
          "real-time run", [this] { rt_->run(io::ClockMode::RealTime, opt_.span); },
          [this](std::string_view) {
            rt_->request_stop();
            run_guarded(
                "real-time run stop", [this] { rt_->finish(); }, [](std::string_view) {});
          });
    });
  }
}

std::optional<VarInfo> Debugger::resolve(const std::string& name, bool& image, std::string& err) {
  if (!name.empty() && name[0] == '%') {
    auto r = io::parse_iec_address(name);
    if (!r.address) {
      err = r.error;
      return std::nullopt;
    }
    if (!rt_->image().contains(*r.address)) {
      err = name + " lies outside the image";
      return std::nullopt;
    }
    VarInfo v;
    v.path = r.address->to_string();
    v.type = type_for(r.address->size);
    v.address = *r.address;
    v.image_ptr = rt_->image().at(*r.address);
    v.order = rt_->byte_order();
    image = true;
    return v;
  }
  const VarInfo* v = rt_->vars().find(name);
  if (!v) {
    err = "unknown variable '" + name + "' (plcrun CONFIG --list-vars lists them)";
    return std::nullopt;
  }
  VarInfo out = *v;
  image = v->address.has_value();
  if (image) {
    // Act on the global image, which belongs to no task: it is read under
    // the image lock, never as a quiet variable of the task.
    out.image_ptr = rt_->image().at(*v->address);
    out.task = -1;
  }
  return out;
}

// ---------------------------------------------------------------- hooks

void Debugger::apply_write(TaskRuntime& t, const VarInfo& v, const void* value) {
  VarRegistry::write(v, value);
  if (recorder_) recorder_->note_write(t, v, value);
}

void Debugger::after_latch(TaskRuntime& t, io::ProcessImage& global) {
  std::lock_guard<std::mutex> lock(mu_);
  if (carry_) carry_over(t);  // an online change switched t at this latch (reload.cpp)
  for (const Force& f : forces_)
    if (f.image && f.var.address->area == io::Area::Input) apply_write(t, f.var, &f.value);
  if (recorder_) recorder_->after_latch(t, global);
}

void Debugger::on_answer(TaskRuntime& t, std::size_t device, const io::RecordRequest& r) {
  std::lock_guard<std::mutex> lock(mu_);
  if (recorder_) recorder_->on_answer(t, device, r);
}

void Debugger::before_programs(TaskRuntime& t, const ScanContext& ctx) {
  // A write into the global image needs the image lock, and that lock comes
  // before mu_; only a scan with such writes waiting takes it.
  if (image_writes_pending_.load(std::memory_order_acquire)) {
    rt_->with_image_locked([&] { apply_writes(t, ctx, true); });
  } else {
    apply_writes(t, ctx, false);
  }
}

void Debugger::apply_writes(TaskRuntime& t, const ScanContext& ctx, bool image_locked) {
  std::lock_guard<std::mutex> lock(mu_);
  auto in_task_image = [&t](VarInfo v) {
    v.image_ptr = t.image.at(*v.address);
    return v;
  };
  for (auto it = writes_.begin(); it != writes_.end();) {
    if (it->image ? image_locked : it->task == static_cast<int>(t.order)) {
      if (it->image) {
        const VarInfo v = in_task_image(it->var);
        apply_write(t, v, &it->value);
        if (v.address->area != io::Area::Input) apply_write(t, it->var, &it->value);
      } else {
        apply_write(t, it->var, &it->value);
      }
      it = writes_.erase(it);
    } else {
      ++it;
    }
  }
  if (image_locked) image_writes_pending_.store(false, std::memory_order_relaxed);
  for (const Force& f : forces_) {
    if (f.image) {
      if (f.var.address->area != io::Area::Input) apply_write(t, in_task_image(f.var), &f.value);
    } else if (f.var.task == static_cast<int>(t.order)) {
      apply_write(t, f.var, &f.value);
    }
  }
  if (recorder_) recorder_->before_programs(t, ctx);
}

void Debugger::before_program(TaskRuntime& t, std::size_t index, const ScanContext& ctx) {
  freeze_if_due(t, index);
  std::lock_guard<std::mutex> lock(mu_);
  if (recorder_) recorder_->before_program(t, index, ctx);
}

void Debugger::freeze_if_due(TaskRuntime& t, std::size_t index) {
  if (opt_.mode != io::ClockMode::Virtual || in_freeze_ || !reader_) return;
  const std::string& prog = t.program_names[index];
  bool freeze = false;
  {
    std::lock_guard<std::mutex> lock(mu_);
    for (Breakpoint& b : breaks_) {
      if (b.before_program != prog || (b.cond && !b.cond->holds())) continue;
      if (++b.hits % b.hit_target == 0) freeze = true;
    }
  }
  if (freeze) freeze_loop(t, index);
}

void Debugger::after_programs(TaskRuntime& t, const ScanContext& ctx) {
  std::lock_guard<std::mutex> lock(mu_);
  for (const Force& f : forces_)
    if (!f.image && f.var.task == static_cast<int>(t.order)) apply_write(t, f.var, &f.value);
  if (recorder_) recorder_->after_programs(t, ctx);
}

void Debugger::before_publish(TaskRuntime& t, io::ProcessImage& global) {
  std::lock_guard<std::mutex> lock(mu_);
  for (const Force& f : forces_)
    if (f.image && f.var.address->area != io::Area::Input) apply_write(t, f.var, &f.value);
  if (recorder_) recorder_->before_publish(t, global);
}

void Debugger::on_stop(TaskRuntime& t, io::ProcessImage& global) {
  std::lock_guard<std::mutex> lock(mu_);
  if (recorder_) recorder_->on_stop(t, global);
}

void Debugger::on_scan_end(const TaskRuntime& t, const ScanContext& ctx) {
  // Virtual time: nothing runs concurrently, the image is always readable
  // (with_image_locked takes no lock there).
  if (scan_end_reads_global_.load(std::memory_order_acquire)) {
    rt_->with_image_locked([&] { scan_end(t, ctx, true); });
  } else {
    scan_end(t, ctx, opt_.mode != io::ClockMode::RealTime);
  }
}

void Debugger::note_scan_end_reads() {
  bool reads = trace_ && trace_->running() && trace_->reads_global();
  for (const Breakpoint& b : breaks_) reads |= b.cond && b.cond->reads_global();
  scan_end_reads_global_.store(reads, std::memory_order_release);
}

std::string Debugger::realtime_condition_error(const Condition& c) const {
  if (opt_.mode != io::ClockMode::RealTime) return {};
  std::vector<std::string> names;
  for (const auto& t : rt_->tasks()) names.push_back(t->name);
  return one_task_error(c.variables(), names);
}

void Debugger::scan_end(const TaskRuntime& t, const ScanContext& ctx, bool global_readable) {
  std::lock_guard<std::mutex> lock(mu_);
  if (scan_reads_n_) serve_reads(t);
  ++last_.scans;
  last_.time = ctx.now;
  last_.task = static_cast<int>(t.order);
  // The trace and the conditions read the variables of this task only (in
  // real time the commands refuse others: one_task.hpp), and the global
  // image when it is readable.
  if (trace_ && trace_->running() && (global_readable || !trace_->reads_global())) {
    int fastest = 0;
    for (const auto& task : rt_->tasks())
      if (task->period == rt_->fastest_period()) {
        fastest = static_cast<int>(task->order);
        break;
      }
    if (trace_->sampling_task(fastest) == static_cast<int>(t.order)) trace_->sample(ctx);
  }
  for (Breakpoint& b : breaks_) {
    if (!b.before_program.empty() || !b.cond) continue;
    if (b.task >= 0 && b.task != static_cast<int>(t.order)) continue;
    if (!global_readable && b.cond->reads_global()) continue;
    if (!b.cond->holds()) continue;
    if (++b.hits % b.hit_target != 0) continue;
    if (!stop_hit_.load()) {
      // The reason is written before stop_hit_ is published: in real time
      // the console thread reads it as soon as it sees stop_hit_.
      stop_reason_ = (b.temporary ? "condition '" + b.text + "' holds"
                                  : "breakpoint " + std::to_string(b.id) + " (" + b.text +
                                        ") hit, " + std::to_string(b.hits) + " hit(s)") +
                     ", after a scan of task '" + t.name + "'";
      if (opt_.mode == io::ClockMode::RealTime) rt_->set_paused(true);
      stop_hit_.store(true);
    }
  }
}

void Debugger::freeze_loop(TaskRuntime& t, std::size_t index) {
  in_freeze_ = true;
  frozen_task_ = &t;
  freeze_action_ = 0;
  if (writer_)
    writer_("frozen before program '" + t.program_names[index] + "' of task '" + t.name +
            "' in scan " + std::to_string(last_.scans + 1) + " (t=" + seconds(rt_->now()) + ")\n" +
            watch_lines());
  while (true) {
    auto line = reader_("[frozen before " + t.program_names[index] + "] > ");
    if (!line) break;
    const auto w = words(*line);
    if (w.empty()) continue;
    if (w[0] == "continue" || w[0] == "c") break;
    if (w[0] == "step" || w[0] == "s") {
      freeze_action_ = 1;
      break;
    }
    if (w[0] == "quit" || w[0] == "q") {
      quit_ = true;
      break;
    }
    if (w[0] == "goto" || w[0] == "run" || w[0] == "record") {
      if (writer_) writer_("not inside a freeze point: 'continue' or 'step' first\n");
      continue;
    }
    const std::string out = execute(*line);
    if (writer_ && !out.empty()) writer_(out);
  }
  in_freeze_ = false;
  frozen_task_ = nullptr;
  if (freeze_action_ == 1 || quit_) {
    stop_reason_ = quit_ ? "quit" : "stepped from the freeze point to the end of the scan";
    stop_hit_ = true;
  }
}

// ---------------------------------------------------------------- run control

bool Debugger::one_scan() {
  if (end_requested()) return false;  // the session ends at this scan boundary
  if (replayer_) return replayer_->step();
  if (rt_->now() >= opt_.span) return false;
  return rt_->step_scan() != nullptr;
}

Debugger::LastScan Debugger::last_scan() const {
  std::lock_guard<std::mutex> lock(mu_);
  return last_;
}

std::string Debugger::stop_report(const std::string& why) {
  const LastScan last = last_scan();
  std::string s = why + "\n  at scan " + std::to_string(last.scans);
  if (last.scans > 0 && last.task >= 0)
    s += " (the last: task '" + rt_->tasks()[std::size_t(last.task)]->name +
         "' at t=" + seconds(last.time) + ")";
  if (replayer_) {
    s += ", replay " + std::to_string(replayer_->scans()) + " scans, " +
         std::to_string(replayer_->mismatches()) + " output mismatch(es)";
    if (replayer_->first_mismatch() >= 0)
      s += ", first at scan " + std::to_string(replayer_->first_mismatch());
    if (!replayer_->error().empty()) s += " (" + replayer_->error() + ")";
  }
  return s + "\n" + watch_lines();
}

std::string Debugger::watch_lines() {
  if (watches_.empty()) return "";
  std::string s, all = describe_values(watches_);
  for (std::size_t b = 0, e; b < all.size(); b = e + 1) {
    e = all.find('\n', b);
    s += "  " + all.substr(b, e - b + 1);
  }
  return s;
}

std::string Debugger::realtime_wait_until_paused(std::optional<TIME> span) {
  // The span counts on the monotonic clock, as the tasks' releases do.
  using Clock = std::chrono::steady_clock;
  const auto deadline = span ? Clock::now() + *span : Clock::time_point::max();
  bool ran_out = false;
  while (!stop_hit_.load() && !interrupted_.load() && !end_requested()) {
    const auto now = Clock::now();
    if (now >= deadline) {
      ran_out = true;
      break;
    }
    std::this_thread::sleep_until(std::min(deadline, now + std::chrono::milliseconds(1)));
  }
  const std::string note = pause_and_settle();
  // The scan thread that stopped us wrote the reason under mu_.
  std::lock_guard<std::mutex> lock(mu_);
  const std::string why = stop_hit_.load() ? stop_reason_
                          : ran_out        ? "ran for " + format_iec_time(*span)
                                           : std::string("interrupted");
  return why + note;
}

std::string Debugger::pause_and_settle() {
  rt_->set_paused(true);
  std::int64_t longest = 0;
  for (const auto& t : rt_->tasks()) longest = std::max<std::int64_t>(longest, t->period.count());
  const auto wait = std::chrono::nanoseconds(std::max<std::int64_t>(1'000'000'000, 3 * longest));
  if (rt_->wait_until_idle(wait)) return "";
  std::string busy;
  for (const auto& t : rt_->tasks())
    if (t->busy.load()) busy += " '" + t->name + "'";
  return "\n  note: still inside a scan:" + busy + " (its variables show when the scan ends)";
}

bool Debugger::task_quiet(const TaskRuntime& t) const {
  if (opt_.mode != io::ClockMode::RealTime) return true;
  // The pause (or the stop) first, then busy: the order the task thread
  // checks them in reverse (TaskRuntime::busy).
  const bool held = (rt_->paused() && t.step_budget.load() <= 0) || t.stopped.load();
  return held && !t.busy.load();
}

std::string Debugger::cmd_step(const std::vector<std::string>& a) {
  std::string task_name;
  std::uint64_t n = 1;
  std::size_t i = 1;
  if (a.size() > 1 && a[1] == "task") {
    if (a.size() < 3) return "usage: step task NAME [N]\n";
    task_name = a[2];
    i = 3;
  }
  if (a.size() > i) {
    auto c = count_arg(a[i]);
    if (!c) return "step: '" + a[i] + "' is not a positive count\n";
    n = *c;
  }
  return step(n, task_name).text;
}

Debugger::Reply Debugger::step(std::uint64_t n, const std::string& task_name) {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  if (n < 1) return {false, "step: the count must be positive\n"};
  const TaskRuntime* target = nullptr;
  if (!task_name.empty()) {
    target = rt_->task(task_name);
    if (!target) return {false, "step: unknown task '" + task_name + "'\n"};
  }
  if (opt_.mode == io::ClockMode::RealTime) {
    // Settled first, so the goal counts only the scans this step lets through.
    pause_and_settle();
    std::vector<std::pair<const TaskRuntime*, std::uint64_t>> goal;
    for (const auto& t : rt_->tasks()) {
      if (target && t.get() != target) continue;
      goal.emplace_back(t.get(), t->stats.scans() + n);
      rt_->allow_scans(*t, static_cast<std::int64_t>(n));
    }
    interrupted_ = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    for (bool done = false; !done && !interrupted_ && !end_requested() &&
                            std::chrono::steady_clock::now() < deadline;) {
      done = true;
      for (const auto& [t, g] : goal) done &= t->stats.scans() >= g || t->stopped.load();
      if (!done) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    const std::string note = pause_and_settle();
    return {true, stop_report("stepped " + std::to_string(n) + " scan(s) of " +
                              (target ? "task '" + task_name + "'" : "each task") + note)};
  }
  // Virtual time: stepping ignores breakpoints (as TwinCAT's single cycle),
  // not Ctrl-C.
  std::uint64_t done = 0;
  std::string why;
  interrupted_ = false;
  while (done < n) {
    if (interrupted_) {
      why = "; interrupted";
      break;
    }
    const std::uint64_t before = target ? target->stats.scans() : 0;
    if (!one_scan()) {
      why = "; the session has ended (no more scans)";
      break;
    }
    if (!target || target->stats.scans() > before) ++done;
    if (quit_) break;
  }
  stop_hit_ = false;
  return {true, stop_report("stepped " + std::to_string(done) + " scan(s)" +
                            (target ? " of task '" + task_name + "'" : "") + why)};
}

std::string Debugger::cmd_continue(const std::vector<std::string>& a, bool until) {
  if (until) {
    if (a.size() < 3) return "usage: run until CONDITION\n";
    return run_until(rest_after(joined_line_, 2)).text;
  }
  std::optional<TIME> for_time;
  if (a.size() >= 2 && a[1] == "for") {
    if (a.size() != 3) return "usage: continue for DURATION (e.g. continue for 5s)\n";
    for_time = parse_iec_time(a[2]);
    if (!for_time) return "continue for: " + iec_time_error(a[2]) + "\n";
  } else if (a.size() > 1) {
    return "usage: continue [for DURATION]\n";
  }
  return continue_running(for_time).text;
}

Debugger::Reply Debugger::run_until(std::string_view text) {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  std::string err;
  auto cond =
      Condition::compile(std::string(text), rt_->vars(), rt_->image(), rt_->byte_order(), err);
  if (!cond) return {false, "run until: " + err + "\n"};
  if (err = realtime_condition_error(*cond); !err.empty())
    return {false, "run until: " + err + "\n"};
  Breakpoint b;
  b.id = -1;
  b.text = cond->text();
  b.task = cond->task();
  b.cond = std::move(cond);
  b.temporary = true;
  {
    std::lock_guard<std::mutex> lock(mu_);
    breaks_.push_back(std::move(b));
    note_scan_end_reads();
  }
  return run_and_report(std::nullopt, true);
}

Debugger::Reply Debugger::continue_running(std::optional<TIME> for_time) {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  if (for_time) {
    if (for_time->count() <= 0)
      return {false, "continue for: the duration must be positive, got " +
                         format_iec_time(*for_time) + "\n"};
    if (*for_time > TIME::max() - rt_->now())
      return {false, "continue for: " + format_iec_time(*for_time) +
                         " from now lies beyond the end of TIME (" + format_iec_time(TIME::max()) +
                         ")\n"};
  }
  return run_and_report(for_time, false);
}

Debugger::Reply Debugger::run_and_report(std::optional<TIME> for_time, bool until) {
  stop_hit_ = false;
  interrupted_ = false;
  std::string why;
  if (opt_.mode == io::ClockMode::RealTime) {
    rt_->set_paused(false);
    if (!until && !for_time) return {true, "running (pause, or a breakpoint, stops it)\n"};
    why = realtime_wait_until_paused(for_time);
  } else {
    const TIME end = for_time ? rt_->now() + *for_time : opt_.span;
    while (true) {
      if (stop_hit_) {
        why = stop_reason_;
        break;
      }
      if (end_requested()) {
        why = "the session is ending (signal)";
        break;
      }
      if (interrupted_) {
        why = "interrupted";
        break;
      }
      if (quit_) break;
      if (for_time && rt_->now() >= end) {
        why = "ran for " + format_iec_time(*for_time);
        break;
      }
      if (!one_scan()) {
        why = replayer_ ? "the recording has ended"
                        : "the session has ended (end of --for span or all tasks stopped)";
        break;
      }
    }
  }
  if (until) {
    std::lock_guard<std::mutex> lock(mu_);
    std::erase_if(breaks_, [](const Breakpoint& b) { return b.temporary; });
    note_scan_end_reads();
  }
  stop_hit_ = false;
  return {true, stop_report("stopped: " + why)};
}

std::string Debugger::cmd_break(const std::vector<std::string>& a) {
  if (a.size() < 2) return breaks_list();
  std::string before_program, cond_text;
  std::uint64_t hit_target = 1;
  if (a[1] == "before") {
    if (a.size() < 3) return "usage: break before PROGRAM [if CONDITION] [hits N]\n";
    before_program = a[2];
    if (a.size() > 3 && a[3] == "if") {
      cond_text = rest_after(joined_line_, 4);
    } else if (a.size() > 3) {
      // No condition: only "hits N" may follow.
      if (a[3] != "hits" || a.size() != 5)
        return "usage: break before PROGRAM [if CONDITION] [hits N]\n";
      auto c = count_arg(a[4]);
      if (!c) return "break: 'hits' needs a positive count\n";
      hit_target = *c;
    }
  } else {
    cond_text = rest_after(joined_line_, 1);
  }
  // A trailing "hits N": stop on every N-th hit.
  auto ww = words(cond_text);
  if (ww.size() >= 2 && ww[ww.size() - 2] == "hits") {
    auto c = count_arg(ww.back());
    if (!c) return "break: 'hits' needs a positive count\n";
    hit_target = *c;
    cond_text.resize(cond_text.rfind("hits"));
    while (!cond_text.empty() && std::isspace(static_cast<unsigned char>(cond_text.back())))
      cond_text.pop_back();
  } else if (before_program.empty() && a.size() > 2 && a[a.size() - 2] == "hits") {
    auto c = count_arg(a.back());
    if (!c) return "break: 'hits' needs a positive count\n";
    hit_target = *c;
  }
  if (cond_text.empty() && before_program.empty())
    return "usage: break CONDITION [hits N] | break before PROGRAM [if CONDITION] [hits N]\n";
  return add_breakpoint(cond_text, hit_target, before_program).text;
}

Debugger::Reply Debugger::add_breakpoint(std::string_view condition, std::uint64_t hits,
                                         const std::string& before_program) {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  const std::string cond_text(condition);
  if (hits < 1) return {false, "break: 'hits' needs a positive count\n"};
  if (cond_text.empty() && before_program.empty())
    return {false, "break: a condition or a program is needed\n"};
  Breakpoint b;
  b.hit_target = hits;
  if (!before_program.empty()) {
    bool found = false;
    for (const auto& t : rt_->tasks())
      for (const auto& p : t->program_names) found |= p == before_program;
    if (!found) return {false, "break: no task runs a program named '" + before_program + "'\n"};
    b.before_program = before_program;
  }
  if (!cond_text.empty()) {
    std::string err;
    b.cond = Condition::compile(cond_text, rt_->vars(), rt_->image(), rt_->byte_order(), err);
    if (!b.cond) return {false, "break: " + err + "\n"};
    if (err = realtime_condition_error(*b.cond); !err.empty())
      return {false, "break: " + err + "\n"};
    b.task = b.cond->task();
  }
  if (!b.before_program.empty() && opt_.mode == io::ClockMode::RealTime)
    return {false,
            "break before: freeze points need virtual time (they would stall a real-time task)\n"};
  b.id = next_break_id_++;
  b.text = b.before_program.empty()
               ? cond_text
               : "before " + b.before_program + (cond_text.empty() ? "" : " if " + cond_text);
  std::string out = "breakpoint " + std::to_string(b.id) + ": " + b.text +
                    (b.hit_target > 1 ? " (every " + std::to_string(b.hit_target) + " hits)" : "") +
                    "\n";
  std::lock_guard<std::mutex> lock(mu_);
  breaks_.push_back(std::move(b));
  note_scan_end_reads();
  return {true, out};
}

Debugger::Reply Debugger::add_breakpoint(ConditionCode code, std::vector<ConditionOperand> operands,
                                         std::uint64_t hits) {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  if (hits < 1) return {false, "break: 'hits' needs a positive count\n"};
  std::string err;
  auto cond = Condition::bind(std::move(code), std::move(operands), rt_->vars(), rt_->image(),
                              rt_->byte_order(), err);
  if (!cond) return {false, "break: " + err + "\n"};
  if (err = realtime_condition_error(*cond); !err.empty()) return {false, "break: " + err + "\n"};
  Breakpoint b;
  b.hit_target = hits;
  b.task = cond->task();
  b.text = cond->text();
  b.cond = std::move(cond);
  b.id = next_break_id_++;
  std::string out = "breakpoint " + std::to_string(b.id) + ": " + b.text +
                    (b.hit_target > 1 ? " (every " + std::to_string(b.hit_target) + " hits)" : "") +
                    "\n";
  std::lock_guard<std::mutex> lock(mu_);
  breaks_.push_back(std::move(b));
  note_scan_end_reads();
  return {true, out};
}

Debugger::Reply Debugger::delete_breakpoint(const std::string& id) {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  std::lock_guard<std::mutex> lock(mu_);
  const std::size_t before = breaks_.size();
  if (id == "all")
    breaks_.clear();
  else
    std::erase_if(breaks_, [&](const Breakpoint& b) { return std::to_string(b.id) == id; });
  note_scan_end_reads();
  return before == breaks_.size()
             ? Reply{false, "delete: no breakpoint " + id + "\n"}
             : Reply{true,
                     "deleted " + std::to_string(before - breaks_.size()) + " breakpoint(s)\n"};
}

Debugger::Reply Debugger::pause() {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  if (opt_.mode == io::ClockMode::Virtual)
    return {true, "paused (in virtual time the cell is paused between commands)\n"};
  const std::string note = pause_and_settle();
  return {true, "paused: the logic is held at its next release; the fieldbus keeps exchanging" +
                    note + "\n"};
}

std::string Debugger::breaks_list() {
  std::lock_guard<std::mutex> lock(mu_);
  if (breaks_.empty()) return "no breakpoints\n";
  std::string s;
  for (const Breakpoint& b : breaks_)
    if (!b.temporary)
      s += "  " + std::to_string(b.id) + ": " + b.text + "  hits " + std::to_string(b.hits) +
           (b.hit_target > 1 ? " (stops every " + std::to_string(b.hit_target) + ")" : "") + "\n";
  return s;
}

// ---------------------------------------------------------------- values

// "NAME = VALUE  (TYPE ADDRESS[, image: V][, forced])": program variables
// as their program saw them in its last scan; for located variables the
// global image too when it differs (a force or another task changed it).
std::string Debugger::describe_value(const std::string& name) { return describe_values({name}); }

std::string Debugger::describe_values(const std::vector<std::string>& names) {
  std::string out;
  for (const Value& v : read(names)) {
    if (!v.error.empty()) {
      out += v.name + ": " + v.error + "\n";
      continue;
    }
    out += v.name + " = " + v.text + "  (" + to_string(v.type) +
           (v.address ? " " + v.address->to_string() : "") +
           (v.image.empty() ? "" : ", image: " + v.image) + (v.forced ? ", forced" : "") + ")\n";
  }
  return out;
}

std::vector<Debugger::Value> Debugger::read(const std::vector<std::string>& names) {
  const std::vector<TypedValue> typed = read_typed(names);
  std::vector<Value> out(typed.size());
  for (std::size_t i = 0; i < typed.size(); ++i) {
    const TypedValue& t = typed[i];
    Value& v = out[i];
    v.name = t.name;
    v.error = t.error;
    if (!t.error.empty()) continue;
    v.type = t.type;
    v.address = t.address;
    v.text = t.no_value.empty() ? format_value(t.type, t.bytes) : "<" + t.no_value + ">";
    if (t.image_differs) v.image = format_value(t.type, t.image);
    v.forced = t.forced;
  }
  return out;
}

std::vector<Debugger::TypedValue> Debugger::read_typed(const std::vector<std::string>& names) {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  // Resolve everything first, then read all values at one point.
  struct Line {
    std::string name, error;
    VarInfo shown, global;
    bool image = false, compare = false;
    std::size_t at = 0;
  };
  std::vector<Line> lines(names.size());
  std::vector<VarInfo> reads;
  for (std::size_t i = 0; i < names.size(); ++i) {
    Line& l = lines[i];
    l.name = names[i];
    auto g = resolve(l.name, l.image, l.error);
    if (!g) continue;
    const VarInfo* reg = rt_->vars().find(l.name);
    l.shown = reg ? *reg : *g;
    l.global = *g;
    l.compare = reg && l.image;
    l.at = reads.size();
    reads.push_back(l.shown);
    if (l.compare) reads.push_back(l.global);
  }
  const std::vector<RawValue> raw = read_raw(reads);
  std::vector<TypedValue> out(lines.size());
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const Line& l = lines[i];
    TypedValue& v = out[i];
    v.name = l.name;
    v.error = l.error;
    if (!l.error.empty()) continue;
    v.type = l.global.type;
    v.address = l.global.address;
    v.no_value = raw[l.at].error;
    std::memcpy(v.bytes, raw[l.at].bytes, sizeof v.bytes);
    if (l.compare) {  // the global image is read under its lock: always a value
      const std::size_t n = size_of(v.type);  // located: never a STRING
      if (!v.no_value.empty() || std::memcmp(raw[l.at + 1].bytes, raw[l.at].bytes, n) != 0) {
        v.image_differs = true;
        std::memcpy(v.image, raw[l.at + 1].bytes, std::min(n, sizeof v.image));
      }
    }
    std::lock_guard<std::mutex> lock(mu_);
    for (const Force& f : forces_)
      v.forced |= f.name == l.name || (f.image && l.image && f.var.address == l.global.address);
  }
  return out;
}

std::vector<std::string> Debugger::read_values(const std::vector<VarInfo>& vars) {
  const std::vector<RawValue> raw = read_raw(vars);
  std::vector<std::string> out(vars.size());
  for (std::size_t i = 0; i < vars.size(); ++i)
    out[i] =
        raw[i].error.empty() ? format_value(vars[i].type, raw[i].bytes) : "<" + raw[i].error + ">";
  return out;
}

std::vector<Debugger::RawValue> Debugger::read_raw(const std::vector<VarInfo>& vars) {
  std::vector<RawValue> out(vars.size());
  for (std::size_t i = 0; i < vars.size(); ++i)
    if (vars[i].type == VarType::STRING) new (out[i].bytes) STRING();
  // A variable of task t lives in t's program memory or image copy; one of
  // no task (an address) in the global image, which the tasks' latch and
  // merge write under the image lock. The global image is read last, so it
  // is at least as new as the scans the task variables come from.
  std::vector<std::size_t> at_scan_end, global;
  for (std::size_t i = 0; i < vars.size(); ++i) {
    const VarInfo& v = vars[i];
    if (v.task < 0) {
      global.push_back(i);
    } else if (task_quiet(*rt_->tasks()[std::size_t(v.task)])) {
      VarRegistry::read(v, out[i].bytes);  // nothing writes it now
    } else {
      at_scan_end.push_back(i);
    }
  }
  for (std::size_t first = 0; first < at_scan_end.size(); first += kMaxScanReads) {
    const std::size_t n = std::min(kMaxScanReads, at_scan_end.size() - first);
    std::unique_lock<std::mutex> lock(mu_);
    for (std::size_t k = 0; k < n; ++k) {
      ScanRead& r = scan_reads_[k];
      r.var = &vars[at_scan_end[first + k]];
      r.done = false;
      if (r.var->type == VarType::STRING) new (r.value) STRING();
    }
    scan_reads_n_ = n;
    // A 1 ms task answers within a few ms; one that a breakpoint paused
    // meanwhile never does, and is then quiet.
    std::int64_t longest = 0;
    for (std::size_t k = 0; k < n; ++k)
      longest = std::max<std::int64_t>(
          longest, rt_->tasks()[std::size_t(scan_reads_[k].var->task)]->period.count());
    const auto wait = std::chrono::nanoseconds(std::max<std::int64_t>(100'000'000, 3 * longest));
    reads_cv_.wait_for(lock, wait, [this, n] {
      for (std::size_t k = 0; k < n; ++k)
        if (!scan_reads_[k].done) return false;
      return true;
    });
    scan_reads_n_ = 0;
    for (std::size_t k = 0; k < n; ++k) {
      ScanRead& r = scan_reads_[k];
      RawValue& o = out[at_scan_end[first + k]];
      const TaskRuntime& t = *rt_->tasks()[std::size_t(r.var->task)];
      if (r.done) {
        std::memcpy(o.bytes, r.value, sizeof o.bytes);
      } else if (task_quiet(t)) {
        VarRegistry::read(*r.var, o.bytes);
      } else {
        o.error = "no value: task '" + t.name + "' did not finish a scan in " +
                  format_iec_time(TIME(wait));
      }
    }
  }
  if (!global.empty())
    rt_->with_image_locked([&] {
      for (std::size_t i : global) VarRegistry::read(vars[i], out[i].bytes);
    });
  return out;
}

void Debugger::serve_reads(const TaskRuntime& t) {
  bool any = false;
  for (std::size_t k = 0; k < scan_reads_n_; ++k) {
    ScanRead& r = scan_reads_[k];
    if (r.done || r.var->task != static_cast<int>(t.order)) continue;
    VarRegistry::read(*r.var, r.value);  // a copy, no allocation
    r.done = true;
    any = true;
  }
  if (any) reads_cv_.notify_all();
}

std::string Debugger::cmd_print(const std::vector<std::string>& a) {
  if (a.size() < 2) return "usage: print PATH|ADDRESS ...\n";
  return describe_values(std::vector<std::string>(a.begin() + 1, a.end()));
}

std::string Debugger::cmd_write(const std::vector<std::string>& a, bool force) {
  const char* what = force ? "force" : "write";
  if (a.size() < 3) return std::string("usage: ") + what + " PATH|ADDRESS VALUE\n";
  return write_or_force(a[1], rest_after(joined_line_, 2), force).text;
}

Debugger::Reply Debugger::write(const std::string& name, std::string_view value) {
  return write_or_force(name, value, false);
}

Debugger::Reply Debugger::force(const std::string& name, std::string_view value) {
  return write_or_force(name, value, true);
}

Debugger::Reply Debugger::write_or_force(const std::string& name, std::string_view text,
                                         bool force) {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  const char* what = force ? "force" : "write";
  bool image = false;
  std::string err;
  auto v = resolve(name, image, err);
  if (!v) return {false, std::string(what) + ": " + err + "\n"};
  if (v->type == VarType::STRING)
    return {false, std::string(what) + ": STRING variables cannot be written from the debugger\n"};
  // The write policy (reflect.hpp): internal state is refused whatever the
  // value; a block's write check sees the value.
  if (v->read_only)
    return {false, std::string(what) + " " + name + ": refused, " +
                       VarRegistry::check_write(*v, nullptr) + "\n"};
  std::uint64_t value = 0;
  const std::string value_text(text);
  err = parse_value(v->type, value_text, &value);
  if (err.empty()) err = VarRegistry::check_write(*v, &value);
  if (!err.empty()) return {false, std::string(what) + " " + name + ": " + err + "\n"};
  return apply_write_or_force(name, *v, image, value, force);
}

Debugger::Reply Debugger::write_raw(const std::string& name, const void* value) {
  return write_or_force_raw(name, value, false);
}

Debugger::Reply Debugger::force_raw(const std::string& name, const void* value) {
  return write_or_force_raw(name, value, true);
}

Debugger::Reply Debugger::write_or_force_raw(const std::string& name, const void* raw, bool force) {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  const char* what = force ? "force" : "write";
  bool image = false;
  std::string err;
  auto v = resolve(name, image, err);
  if (!v) return {false, std::string(what) + ": " + err + "\n"};
  if (v->type == VarType::STRING)
    return {false, std::string(what) + ": STRING variables cannot be written from the debugger\n"};
  if (v->read_only)
    return {false, std::string(what) + " " + name + ": refused, " +
                       VarRegistry::check_write(*v, nullptr) + "\n"};
  std::uint64_t value = 0;
  std::memcpy(&value, raw, size_of(v->type));
  err = check_raw_value(v->type, &value);
  if (err.empty()) err = VarRegistry::check_write(*v, &value);
  if (!err.empty()) return {false, std::string(what) + " " + name + ": " + err + "\n"};
  return apply_write_or_force(name, *v, image, value, force);
}

Debugger::Reply Debugger::apply_write_or_force(const std::string& name, const VarInfo& v,
                                               bool image, std::uint64_t value, bool force) {
  const char* what = force ? "force" : "write";
  std::uint64_t original = 0;  // the value before a force (read consistently)
  if (force) {
    const RawValue now = read_raw({v}).front();
    if (!now.error.empty())
      return {false, std::string(what) + " " + name + ": " + now.error + "\n"};
    std::memcpy(&original, now.bytes, sizeof original);
  }
  std::lock_guard<std::mutex> lock(mu_);
  if (!force) {
    if (in_freeze_) {
      // Inside a freeze point the scan is under way: write straight into the
      // task's view (program variable, or located variable's task image).
      const VarInfo* reg = rt_->vars().find(name);
      apply_write(*frozen_task_, reg ? *reg : v, &value);
      if (image) apply_write(*frozen_task_, v, &value);
      return {true, "wrote " + name + " := " + format_value(v.type, &value) +
                        " (now, inside the scan)\n"};
    }
    writes_.push_back({name, v, image, value, image ? -1 : v.task});
    if (image) image_writes_pending_.store(true, std::memory_order_release);
    return {true, "will write " + name + " := " + format_value(v.type, &value) +
                      " at the start of the next scan\n"};
  }
  for (Force& f : forces_)
    if (f.name == name) {
      f.value = value;
      return {true, "force " + name + " := " + format_value(v.type, &value) + " (changed)\n"};
    }
  forces_.push_back({name, v, image, value, original});
  return {true, "force " + name + " := " + format_value(v.type, &value) +
                    " (every scan until unforce)\n"};
}

std::string Debugger::cmd_unforce(const std::vector<std::string>& a) {
  if (a.size() < 2) return "usage: unforce PATH|ADDRESS|all [restore]\n";
  return unforce(a[1], a.size() > 2 && a[2] == "restore").text;
}

Debugger::Reply Debugger::unforce(const std::string& name, bool restore) {
  const Reply r =
      unforce_if([&name](const std::string& n) { return name == "all" || n == name; }, restore);
  return r.ok ? r : Reply{false, "unforce: '" + name + "' is not forced\n"};
}

Debugger::Reply Debugger::unforce_if(const std::function<bool(const std::string&)>& release,
                                     bool restore) {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  // One hold of mu_ for all of them: the scans apply forces under it.
  std::lock_guard<std::mutex> lock(mu_);
  std::string s;
  for (auto it = forces_.begin(); it != forces_.end();) {
    if (release(it->name)) {
      if (restore) {
        writes_.push_back(
            {it->name, it->var, it->image, it->original, it->image ? -1 : it->var.task});
        if (it->image) image_writes_pending_.store(true, std::memory_order_release);
      }
      s += "unforced " + it->name +
           (restore ? ", restoring " + format_value(it->var.type, &it->original)
                    : ", keeping the value") +
           "\n";
      it = forces_.erase(it);
    } else {
      ++it;
    }
  }
  return s.empty() ? Reply{false, "unforce: nothing to release\n"} : Reply{true, s};
}

std::vector<std::string> Debugger::forced() {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  std::lock_guard<std::mutex> lock(mu_);
  std::vector<std::string> out;
  for (const Force& f : forces_) out.push_back(f.name);
  return out;
}

std::string Debugger::forces_list() {
  std::lock_guard<std::mutex> lock(mu_);
  if (forces_.empty()) return "no forces\n";
  std::string s;
  for (const Force& f : forces_)
    s += "  " + f.name + " := " + format_value(f.var.type, &f.value) +
         "  (before: " + format_value(f.var.type, &f.original) + ")\n";
  return s;
}

std::string Debugger::cmd_watch(const std::vector<std::string>& a, bool add) {
  if (a.size() < 2) {
    if (watches_.empty()) return "no watches\n";
    return watch_lines();
  }
  std::string s;
  for (std::size_t i = 1; i < a.size(); ++i) {
    if (add) {
      bool image = false;
      std::string err;
      if (!resolve(a[i], image, err)) {
        s += "watch: " + err + "\n";
        continue;
      }
      if (std::find(watches_.begin(), watches_.end(), a[i]) == watches_.end())
        watches_.push_back(a[i]);
    } else {
      std::erase(watches_, a[i]);
    }
  }
  return s + (add ? watch_lines() : "");
}

// ---------------------------------------------------------------- trace, record, goto

std::string Debugger::cmd_trace(const std::vector<std::string>& a) {
  std::lock_guard<std::mutex> lock(mu_);  // the sampling scan thread holds it
  if (a.size() < 2 || a[1] == "status") return "trace: " + trace_->describe() + "\n";
  const std::string& sub = a[1];
  if (sub == "add") {
    if (a.size() < 3) return "usage: trace add PATH|ADDRESS ...\n";
    std::string s;
    for (std::size_t i = 2; i < a.size(); ++i) {
      const std::string err = trace_->add(a[i]);
      if (!err.empty())
        s += "trace add: " + err + "\n";
      else
        trace_spec_.push_back("add " + a[i]);
    }
    return s + "trace: " + trace_->describe() + "\n";
  }
  if (sub == "clear") {
    if (trace_->running()) return "trace: stop it first\n";
    trace_->clear();
    std::erase_if(trace_spec_, [](const std::string& s) { return s.rfind("add ", 0) == 0; });
    return "trace: cleared\n";
  }
  if (sub == "trigger") {
    const std::string cond = rest_after(joined_line_, 2);
    const std::string err = trace_->set_trigger(cond == "off" ? "" : cond);
    if (!err.empty()) return "trace trigger: " + err + "\n";
    std::erase_if(trace_spec_, [](const std::string& s) { return s.rfind("trigger", 0) == 0; });
    if (cond != "off" && !cond.empty()) trace_spec_.push_back("trigger " + cond);
    return "trace: " + trace_->describe() + "\n";
  }
  if (sub == "pre") {
    auto n = a.size() > 2 ? parse_iec_unsigned(a[2]) : std::nullopt;
    if (!n || *n > 1'000'000) return "usage: trace pre ROWS (0 .. 1000000)\n";
    trace_->set_pretrigger(*n);
    std::erase_if(trace_spec_, [](const std::string& s) { return s.rfind("pre ", 0) == 0; });
    trace_spec_.push_back("pre " + std::to_string(*n));
    return "trace: " + trace_->describe() + "\n";
  }
  if (sub == "start") {
    if (a.size() < 3) return "usage: trace start FILE.csv|FILE.vcd\n";
    const std::string err = trace_->start(a[2]);
    note_scan_end_reads();
    return err.empty() ? "trace: " + trace_->describe() + "\n" : "trace start: " + err + "\n";
  }
  if (sub == "stop") {
    const std::uint64_t rows = trace_->rows_written();
    trace_->stop();
    note_scan_end_reads();
    return "trace: stopped, " + std::to_string(rows) + " rows written\n";
  }
  return "trace: unknown subcommand '" + sub +
         "' (add, clear, trigger, pre, start, stop, status)\n";
}

std::string Debugger::cmd_record(const std::vector<std::string>& a) {
  if (a.size() < 2)
    return recorder_ ? "recording, " + std::to_string(recorder_->scans()) + " scans so far\n"
                     : "not recording\n";
  if (a[1] == "stop") {
    std::unique_ptr<Recorder> r;
    {
      std::lock_guard<std::mutex> lock(mu_);  // no scan thread is inside it after this
      r = std::move(recorder_);
    }
    if (!r) return "not recording\n";
    const std::string err = r->close();
    const std::string n = std::to_string(r->scans());
    return err.empty() ? "recording stopped, " + n + " scans\n"
                       : "record: the recording FAILED after " + n + " scans: " + err + "\n";
  }
  if (replayer_) return "record: this session replays a recording already\n";
  if (recorder_) return "record: already recording (record stop first)\n";
  std::unique_ptr<Recorder> r;
  try {
    // Opened here, without mu_: the scans never wait on the file system.
    r = std::make_unique<Recorder>(*rt_, a[1], Recorder::Attach::ByCaller);
  } catch (const std::exception& e) {
    return std::string("record: ") + e.what() + "\n";
  }
  {
    std::lock_guard<std::mutex> lock(mu_);
    r->arm();
    recorder_ = std::move(r);
  }
  std::string note;
  if (const std::uint64_t at = scan_count(); at > 0)
    note = "note: the recording starts at scan " + std::to_string(at) +
           " (or the first scan after it with no acyclic request in flight) with a snapshot of the "
           "state the programs declare in PLC_REFLECT (all library blocks "
           "declare theirs); state a program keeps undeclared is not in it and would show as "
           "differences in the replay. A recording from scan 0 (goto 0 first) needs no snapshot.\n";
  return "recording every scan's inputs into " + a[1] + "\n" + note;
}

std::string Debugger::cmd_goto(const std::vector<std::string>& a) {
  if (opt_.mode != io::ClockMode::Virtual) return "goto needs virtual time\n";
  if (a.size() < 2) return "usage: goto SCAN\n";
  auto n = parse_iec_unsigned(a[1]);
  if (!n) return "goto: '" + a[1] + "' is not a scan number\n";
  std::string note;
  if (*n < scan_count() && !reloaded_.empty())
    return "goto: " + reloaded_ +
           " (reload): going back re-runs the session from the start, which needs the old build "
           "(gone from the library's path); a recording's replay can go back across a change\n";
  if (*n < scan_count()) {
    // Backwards: rebuild the cell and run forward from the start (the
    // simulation, or the recording, reproduces the same scans exactly).
    if (recorder_) note += "; recording stopped";
    if (trace_ && trace_->running()) note += "; trace stopped";
    build();
    note = "; re-ran from the start" + note;
  }
  interrupted_ = false;
  while (scan_count() < *n) {
    if (interrupted_) {
      note += "; interrupted";
      break;
    }
    if (!one_scan()) {
      note += "; the session ends at scan " + std::to_string(scan_count());
      break;
    }
  }
  stop_hit_ = false;
  return stop_report("at scan " + std::to_string(scan_count()) + note);
}

// IEC 61131-3 restart of the running cell, from memory (the session keeps
// no retain file): warm keeps RETAIN and PERSISTENT variables, cold only
// PERSISTENT; everything else, the devices included, starts over.
std::string Debugger::cmd_restart(const std::vector<std::string>& a) {
  if (a.size() != 2 || (a[1] != "warm" && a[1] != "cold")) return "usage: restart warm|cold\n";
  if (opt_.mode != io::ClockMode::Virtual)
    return "restart needs virtual time (in real time: quit, then plcrun --warm or --cold)\n";
  const bool warm = a[1] == "warm";
  RetainConfig no_memory;  // the declared variables (the %M ranges live in the config)
  const retain::Layout old_layout(rt_->vars(), no_memory, rt_->image());
  std::vector<std::uint8_t> values(old_layout.bytes());
  old_layout.capture(-1, true, values);
  std::size_t kept = 0;
  build([&](Runtime& rt) {
    const retain::Layout layout(rt.vars(), no_memory, rt.image());
    for (const retain::Entry& e : layout.entries()) {
      if (!warm && e.cls != RetainClass::Persistent) continue;
      for (const retain::Entry& o : old_layout.entries())
        if (o.path == e.path && o.type == e.type && o.size == e.size) {
          layout.restore(e, values.data() + o.offset);
          ++kept;
          break;
        }
    }
    for (const auto& t : rt.tasks()) t->image.copy_from(rt.image());
  });
  stop_hit_ = false;
  return stop_report(std::string(warm ? "warm" : "cold") + " restart: " + std::to_string(kept) +
                     (warm ? " RETAIN/PERSISTENT" : " PERSISTENT") +
                     " values kept, everything else at its initial value");
}

std::string Debugger::cmd_stats() {
  std::string s;
  char b[256];
  for (const auto& t : rt_->tasks()) {
    const TaskStats st = t->stats.snapshot();  // one consistent set per task
    std::snprintf(b, sizeof b,
                  "task %s: period %s, %llu scans, %llu overruns (%llu skipped)%s\n"
                  "  scan time us: min %.1f avg %.1f p99 %.1f max %.1f\n",
                  t->name.c_str(), format_iec_time(t->period).c_str(),
                  static_cast<unsigned long long>(st.scans),
                  static_cast<unsigned long long>(st.overruns),
                  static_cast<unsigned long long>(st.skipped),
                  st.stop_reason.empty() ? "" : (", STOPPED: " + st.stop_reason).c_str(),
                  st.scan_ns.min() / 1e3, st.scan_ns.mean() / 1e3,
                  st.scan_ns.percentile(0.99) / 1e3, st.scan_ns.max() / 1e3);
    s += b;
    if (st.latency_ns.count()) {
      std::snprintf(
          b, sizeof b,
          "  wake latency us: min %.1f avg %.1f p99 %.1f max %.1f; %llu releases paused\n",
          st.latency_ns.min() / 1e3, st.latency_ns.mean() / 1e3,
          st.latency_ns.percentile(0.99) / 1e3, st.latency_ns.max() / 1e3,
          static_cast<unsigned long long>(st.paused_releases));
      s += b;
    }
  }
  return s;
}

// ---------------------------------------------------------------- dispatch

std::string Debugger::prompt() const {
  if (opt_.mode == io::ClockMode::RealTime)
    return std::string("[realtime ") + (rt_->paused() ? "paused" : "running") + "] > ";
  const LastScan last = last_scan();
  return "[scan " + std::to_string(last.scans) + " t=" + seconds(last.time) + "] > ";
}

std::string Debugger::help() const {
  return R"(commands (virtual time: the cell is paused between commands):
  step [N]                  run N scans (default 1) of any task, ignoring breakpoints
  step task NAME [N]        run until task NAME has done N more scans
  continue [for DURATION]   run until a breakpoint, Ctrl-C, the end, or for a duration
  run until CONDITION       run until CONDITION holds at the end of a scan
  pause                     real time: hold the logic (plugins keep exchanging)
  break CONDITION [hits N]  stop at the end of a scan where CONDITION holds (every N-th hit)
  break before PROG [if CONDITION] [hits N]
                            freeze inside the scan, before program PROG runs (virtual time)
  breaks | delete ID|all    list | remove breakpoints
  print NAME...             value in IEC notation (NAME: variable path or %I/%Q/%M address)
  watch [NAME...] | unwatch NAME...
                            values printed at every stop
  write NAME VALUE          set once, at the start of the next scan
  force NAME VALUE          set every scan (inputs after latch, outputs before publish)
                            (a block's internal state is read-only: --list-vars marks it)
  unforce NAME|all [restore]  release (keep the value, or restore the one before the force)
  forces                    list forced variables
  trace add NAME... | trace trigger CONDITION|off | trace pre ROWS
  trace start FILE.csv|FILE.vcd | trace stop | trace [status]
  record FILE | record stop  record every scan's device inputs for replay (plcrun --replay)
  goto SCAN                 go to scan SCAN, also backwards (re-runs from the start)
  restart warm|cold         restart the cell: warm keeps RETAIN and PERSISTENT values,
                            cold only PERSISTENT; the rest (devices too) starts over
  reload [LIB]              online change: load the new build of a cell library (default:
                            the cell's only one); its programs switch at a scan boundary,
                            keeping every field whose path and type did not change
  stats | status            task statistics | where the session is
  help | quit
conditions: ST syntax, e.g.  Tank.step = 3 AND Tank.level > 16#5000 OR NOT %IX0.1
)";
}

std::string Debugger::execute(std::string_view line_in) {
  std::lock_guard<std::recursive_mutex> session(session_mu_);
  joined_line_ = std::string(line_in);
  const auto a = words(line_in);
  if (a.empty() || a[0][0] == '#') return {};
  const std::string& c = a[0];
  if (c == "help" || c == "h" || c == "?") return help();
  if (c == "quit" || c == "q" || c == "exit") {
    quit_ = true;
    return {};
  }
  if (c == "step" || c == "s") return cmd_step(a);
  if (c == "continue" || c == "c") return cmd_continue(a, false);
  if (c == "run" && a.size() > 1 && a[1] == "until") return cmd_continue(a, true);
  if (c == "pause") return pause().text;
  if (c == "break" || c == "b") return cmd_break(a);
  if (c == "breaks") return breaks_list();
  if (c == "delete" || c == "d") {
    if (a.size() < 2) return "usage: delete ID|all\n";
    return delete_breakpoint(a[1]).text;
  }
  if (c == "print" || c == "p") return cmd_print(a);
  if (c == "watch") return cmd_watch(a, true);
  if (c == "unwatch") return cmd_watch(a, false);
  if (c == "write") return cmd_write(a, false);
  if (c == "force") return cmd_write(a, true);
  if (c == "unforce") return cmd_unforce(a);
  if (c == "forces") return forces_list();
  if (c == "trace") return cmd_trace(a);
  if (c == "record") return cmd_record(a);
  if (c == "goto") return cmd_goto(a);
  if (c == "restart") return cmd_restart(a);
  if (c == "reload") return cmd_reload(a);
  if (c == "stats") return cmd_stats();
  if (c == "status" || c == "where") return stop_report("status");
  return "unknown command '" + c + "' (help lists them)\n";
}

}  // namespace plc::debug
