// Building a cell from its config: plugins, tasks, programs, devices,
// bindings, initial and safe values. Every error points at the config line.
#include <algorithm>
#include <map>
#include <numeric>

#include "plc/cell_library.hpp"
#include "plc/iec_literal.hpp"
#include "plc/runtime.hpp"

namespace plc {
namespace {

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s.empty() ? "none" : s;
}

Mark param_mark(const Params& p, const std::string& key) {
  auto it = p.marks.find(key);
  return it != p.marks.end() ? it->second : p.mark;
}

// "key 'size': expected an integer", unless the message names the key already.
std::string with_key(const io::ParamError& e) {
  const std::string msg = e.what();
  if (e.key.empty() || msg.find("'" + e.key + "'") != std::string::npos) return msg;
  return "key '" + e.key + "': " + msg;
}

std::string range_text(io::Area area, std::size_t byte, std::size_t n) {
  const std::string b = std::string("%") + io::area_letter(area) + "B";
  return b + std::to_string(byte) + ".." + b + std::to_string(byte + n - 1);
}

void set_bits(std::vector<std::uint8_t>& mask, std::size_t byte, std::size_t n) {
  for (std::size_t i = byte; i < byte + n && i < mask.size(); ++i) mask[i] = 0xFF;
}

void add_bound(TaskRuntime& t, io::Area area, std::size_t byte, std::size_t n) {
  if (n)
    t.bound[static_cast<std::size_t>(area)].push_back(
        {static_cast<std::uint32_t>(byte), static_cast<std::uint32_t>(byte + n)});
}

// Sorts the ranges and joins those that overlap or lie close together: a
// gap of a few dozen bytes costs less to copy along than one more copy.
// The gap bytes are no program's, so copying them in and back changes
// nothing (Runtime::scan_latch).
void coalesce(std::vector<ImageRange>& v) {
  constexpr std::uint32_t kJoinGap = 64;
  std::sort(v.begin(), v.end(),
            [](const ImageRange& a, const ImageRange& b) { return a.begin < b.begin; });
  std::vector<ImageRange> out;
  for (const ImageRange& r : v) {
    if (!out.empty() && r.begin <= out.back().end + kJoinGap)
      out.back().end = std::max(out.back().end, r.end);
    else
      out.push_back(r);
  }
  v = std::move(out);
}

}  // namespace

Runtime::Runtime(const CellConfig& cfg) { build(cfg); }

Runtime::~Runtime() {
  if (started_) finish();
  hand_over_left_behind();
}

void Runtime::build(const CellConfig& cfg) {
  const std::string& file = cfg.file;
  auto fail = [&](Mark m, const std::string& msg) -> void { throw ConfigError(file, m, msg); };

  // Cell libraries first: their programs, models and plugins are then found
  // by name as the built-in ones are.
  for (const Item<std::string>& lib : cfg.libraries) {
    try {
      libraries_.push_back(use_cell_library(lib.value));
    } catch (const std::exception& e) {  // CellLibraryError, or e.g. no temporary folder
      fail(lib.mark, "key 'libraries': " + lib.value + ": " + e.what());
    }
  }

  cell_name_ = cfg.cell.value.empty() ? "cell" : cfg.cell.value;
  order_ = cfg.byte_order.value;
  global_.resize(cfg.image);
  safe_q_.assign(cfg.image.outputs, 0);

  // Plugins.
  for (const PluginConfig& pc : cfg.plugins) {
    const io::PluginFactory* f = io::PluginRegistry::instance().find(pc.type.value);
    if (!f)
      fail(pc.type.mark, "unknown plugin type '" + pc.type.value +
                             "' (known: " + joined(io::PluginRegistry::instance().names()) + ")");
    auto p = (*f)();
    try {
      p->configure(pc.params.values);
    } catch (const io::ParamError& e) {
      fail(param_mark(pc.params, e.key), "plugin '" + pc.name.value + "': " + with_key(e));
    } catch (const std::exception& e) {
      // Whatever else a plugin throws for its parameters is still about
      // this entry: a config error at its line, never an uncaught exception.
      fail(pc.mark, "plugin '" + pc.name.value + "': " + e.what());
    }
    plugins_.emplace_back(pc.name.value, std::move(p));
  }

  // Tasks.
  std::map<std::string, int> task_of_program;
  for (std::size_t i = 0; i < cfg.tasks.size(); ++i) {
    const TaskConfig& tc = cfg.tasks[i];
    auto t = std::make_unique<TaskRuntime>();
    t->name = tc.name.value;
    t->period = tc.period.value;
    t->priority = tc.priority.value;
    t->watchdog = tc.watchdog.value;
    t->order = i;
    t->image.resize(cfg.image);
    t->before.resize(cfg.image);
    t->owned_q.assign(cfg.image.outputs, 0);
    for (const auto& p : tc.programs) {
      task_of_program[p.value] = static_cast<int>(i);
      t->program_names.push_back(p.value);
    }
    tasks_.push_back(std::move(t));
    tasks_alive_.fetch_add(1, std::memory_order_relaxed);
  }
  for (const auto& t : tasks_) exec_order_.push_back(t.get());
  std::stable_sort(
      exec_order_.begin(), exec_order_.end(),
      [](const TaskRuntime* a, const TaskRuntime* b) { return a->priority < b->priority; });
  std::int64_t g = 0;
  std::int64_t fastest = INT64_MAX;
  for (std::size_t i = 0; i < tasks_.size(); ++i) {
    g = std::gcd(g, tasks_[i]->period.count());
    fastest = std::min(fastest, tasks_[i]->period.count());
    // Named at the first task whose period makes the tick too fine.
    if (!virtual_clock_error_ && fastest / g > kMaxTicksPerRelease)
      virtual_clock_error_.emplace(
          file, cfg.tasks[i].period.mark,
          "key 'period': virtual time steps the devices every " + format_iec_time(TIME(g)) +
              " (the greatest common divisor of the task periods), " + std::to_string(fastest / g) +
              " steps from one scan of the fastest task to the next (at most " +
              std::to_string(kMaxTicksPerRelease) +
              "): choose periods with a larger common divisor (e.g. whole milliseconds)");
  }
  base_tick_ = TIME(g);
  fastest_period_ = TIME(fastest);
  int default_task = 0;
  for (const auto& t : tasks_) {
    const auto& d = *tasks_[default_task];
    if (t->period < d.period || (t->period == d.period && t->priority < d.priority))
      default_task = static_cast<int>(t->order);
  }

  // Devices: plugin, sizes, addresses, overlap.
  devices_.reserve(cfg.devices.size());
  for (const DeviceConfig& dc : cfg.devices) {
    DeviceRuntime d;
    d.name = dc.name.value;
    d.plugin_name = dc.plugin.value;
    d.plugin = plugin(dc.plugin.value);
    if (!d.plugin)
      fail(dc.plugin.mark,
           "device '" + dc.name.value + "' uses unknown plugin '" + dc.plugin.value + "'");
    d.index = 0;
    for (const auto& other : devices_) d.index += other.plugin_name == d.plugin_name;
    io::DeviceSpec spec{dc.name.value, dc.model.value, dc.params.values};
    try {
      d.sizes = d.plugin->add_device(spec);
    } catch (const io::ParamError& e) {
      const Mark m = e.key == "model" ? dc.model.mark : param_mark(dc.params, e.key);
      fail(m.line ? m : dc.mark, "device '" + dc.name.value + "': " + with_key(e));
    } catch (const std::exception& e) {  // e.g. a description the controller cannot connect
      fail(dc.mark, "device '" + dc.name.value + "': " + e.what());
    }
    // Answers and device states change only at scan boundaries.
    d.plugin->link(d.index).set_deferred(true, &links_tracking_, &state_changes_);
    auto place = [&](const Item<std::string>& addr, std::size_t size, io::Area area,
                     const char* key) -> io::IecAddress {
      io::IecAddress a{area, io::AddrSize::Byte, 0, 0};
      if (size == 0) return a;
      if (addr.value.empty())
        fail(dc.mark, "device '" + dc.name.value + "' has " + std::to_string(size) + " " +
                          (area == io::Area::Input ? "input" : "output") + " bytes: give its '" +
                          key + "' start address (e.g. " +
                          (area == io::Area::Input ? "%IB0" : "%QB0") + ")");
      auto r = io::parse_iec_address(addr.value);
      if (!r.address) fail(addr.mark, "key '" + std::string(key) + "': " + r.error);
      if (r.address->area != area)
        fail(addr.mark, "key '" + std::string(key) + "': " + addr.value + " must be in the " +
                            (area == io::Area::Input ? "%I" : "%Q") + " area");
      if (r.address->size == io::AddrSize::Bit && r.address->bit != 0)
        fail(addr.mark, "key '" + std::string(key) + "': a device's data starts on a byte (%" +
                            std::string(1, io::area_letter(area)) + "B" +
                            std::to_string(r.address->byte) + ")");
      a.byte = r.address->byte;
      const std::size_t have = global_.area(area).size();
      if (a.byte + size > have)
        fail(addr.mark, "key '" + std::string(key) + "': device '" + dc.name.value + "' needs " +
                            std::to_string(size) + " bytes from " + addr.value +
                            " but the image has " + std::to_string(have) + " (raise image." +
                            (area == io::Area::Input ? "inputs" : "outputs") + ")");
      for (const auto& o : devices_) {
        const io::IecAddress& oa = area == io::Area::Input ? o.in : o.out;
        const std::size_t osz =
            area == io::Area::Input ? o.sizes.input_bytes : o.sizes.output_bytes;
        if (osz && a.byte < oa.byte + osz && oa.byte < a.byte + size)
          fail(addr.mark, "key '" + std::string(key) + "': overlapping addresses: device '" +
                              dc.name.value + "' uses " + range_text(area, a.byte, size) +
                              ", which overlaps device '" + o.name + "' (" +
                              range_text(area, oa.byte, osz) + ")");
      }
      return a;
    };
    d.in = place(dc.input, d.sizes.input_bytes, io::Area::Input, "input");
    d.out = place(dc.output, d.sizes.output_bytes, io::Area::Output, "output");
    d.task = default_task;
    if (!dc.task.value.empty()) {
      for (const auto& t : tasks_)
        if (t->name == dc.task.value) d.task = static_cast<int>(t->order);
    }
    devices_.push_back(std::move(d));
  }
  for (auto& d : devices_) tasks_[d.task]->devices.push_back(&d);
  plan_device_io();
  std::vector<bool> device_has_port(devices_.size(), false);

  // Programs: instantiate, apply bindings, register fields, bind to images.
  for (const ProgramConfig& pc : cfg.programs) {
    const ProgramFactory* f = ProgramRegistry::instance().find(pc.type.value);
    if (!f)
      fail(pc.type.mark, "unknown program type '" + pc.type.value +
                             "' (known: " + joined(ProgramRegistry::instance().names()) + ")");
    auto it = task_of_program.find(pc.name.value);
    if (it == task_of_program.end())
      fail(pc.name.mark, "program '" + pc.name.value +
                             "' is not run by any task (list it under a task's 'programs')");
    TaskRuntime& task = *tasks_[it->second];
    std::unique_ptr<Program> prog = (*f)();
    FieldVisitor fv(pc.name.value);
    prog->describe(fv);

    std::map<std::string, Mark> bind_marks;
    for (const auto& [path, target] : pc.bind) {
      const std::string full = pc.name.value + "." + path.value;
      bool done = false;
      for (auto& l : fv.located)
        if (l.path == full) {
          l.var->set_address(target.value);
          bind_marks[full] = target.mark;
          done = true;
        }
      for (auto& p : fv.ports)
        if (p.path == full) {
          p.port->set_device_name(target.value);
          bind_marks[full] = target.mark;
          done = true;
        }
      if (!done)
        fail(path.mark, "key '" + path.value + "': program '" + pc.name.value + "' (" +
                            pc.type.value +
                            ") has no located variable or device port of that name");
    }

    // Registered in declaration order (plain and located variables mixed).
    std::vector<std::pair<std::size_t, VarInfo>> program_vars;
    for (const auto& fld : fv.fields)
      program_vars.emplace_back(fld.seq, plain_var_info(fld, static_cast<int>(task.order)));
    for (const auto& l : fv.located) {
      const Mark m = bind_marks.count(l.path) ? bind_marks[l.path] : pc.mark;
      const std::string addr(l.var->address());
      if (addr.empty())
        fail(m,
             l.path + ": located variable has no address (give one in the code or under 'bind')");
      auto r = io::parse_iec_address(addr);
      if (!r.address) fail(m, l.path + ": " + r.error);
      const auto need = io::addr_size_for(l.type);
      if (!need || *need != r.address->size) {
        static const char* sz[] = {"X", "B", "W", "D", "L"};
        const std::string tn = to_string(l.type);
        const char* article =
            std::string("AEIOU").find(tn[0]) != std::string::npos ? ": an " : ": a ";
        fail(m, l.path + article + tn + " needs a %I" + (need ? sz[int(*need)] : "?") + "/%Q" +
                    (need ? sz[int(*need)] : "?") + "/%M" + (need ? sz[int(*need)] : "?") +
                    " address, got " + addr);
      }
      if (!global_.contains(*r.address))
        fail(m, l.path + ": " + addr + " lies outside the image (" +
                    std::to_string(global_.area(r.address->area).size()) + " bytes in %" +
                    io::area_letter(r.address->area) + ")");
      std::uint8_t* p = task.image.at(*r.address);
      l.var->bind(p, r.address->bit, order_);
      add_bound(task, r.address->area, r.address->byte, r.address->width_bytes());
      if (r.address->area == io::Area::Output) {
        if (r.address->size == io::AddrSize::Bit)
          task.owned_q[r.address->byte] |= static_cast<std::uint8_t>(1U << r.address->bit);
        else
          set_bits(task.owned_q, r.address->byte, r.address->width_bytes());
      }
      VarInfo v;
      v.path = l.path;
      v.type = l.type;
      v.address = *r.address;
      v.image_ptr = p;
      v.order = order_;
      v.task = static_cast<int>(task.order);
      v.read_only = l.access.read_only;
      v.check = l.access.check;
      v.retain = l.retain;
      // Only %M is restored: an input comes from its device at the next
      // latch and an output starts at its safe value (a retained output
      // would be overwritten by the copy-in anyway, OpenPLC v4's bug).
      if (l.retain != RetainClass::None && r.address->area != io::Area::Memory)
        fail(m, l.path + ": " + to_string(l.retain) + " located at " + addr +
                    ": only %M located variables can be retained (keep the value in a plain "
                    "variable or a %M address)");
      program_vars.emplace_back(l.seq, std::move(v));
    }
    std::sort(program_vars.begin(), program_vars.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& [_, v] : program_vars) vars_.add(std::move(v));
    for (const auto& pf : fv.ports) {
      const Mark m = bind_marks.count(pf.path) ? bind_marks[pf.path] : pc.mark;
      const std::string dev(pf.port->device_name());
      if (dev.empty())
        fail(m, pf.path + ": device port names no device (bind it: bind: {" +
                    pf.path.substr(pc.name.value.size() + 1) + ": <device>})");
      DeviceRuntime* d = nullptr;
      for (std::size_t i = 0; i < devices_.size(); ++i)
        if (devices_[i].name == dev) {
          d = &devices_[i];
          device_has_port[i] = true;
        }
      if (!d) fail(m, pf.path + ": unknown device '" + dev + "' (declare it under 'devices')");
      auto in = task.image.area(io::Area::Input).subspan(d->in.byte, d->sizes.input_bytes);
      auto out = task.image.area(io::Area::Output).subspan(d->out.byte, d->sizes.output_bytes);
      pf.port->bind(in, out, &d->plugin->link(d->index));
      add_bound(task, io::Area::Input, d->in.byte, d->sizes.input_bytes);
      add_bound(task, io::Area::Output, d->out.byte, d->sizes.output_bytes);
      set_bits(task.owned_q, d->out.byte, d->sizes.output_bytes);
    }
    task.programs.push_back(prog.get());
    programs_.emplace_back(pc.name.value, std::move(prog));
    program_types_[pc.name.value] = pc.type.value;
    for (const auto& [path, target] : pc.bind)
      program_binds_[pc.name.value][pc.name.value + "." + path.value] = target.value;

    for (const auto& [path, value] : pc.init) {
      const std::string full = pc.name.value + "." + path.value;
      const VarInfo* v = vars_.find(full);
      if (!v)
        fail(path.mark, "key '" + path.value + "': program '" + pc.name.value +
                            "' has no variable of that name");
      // A read-only variable is the key's fault, whatever the value.
      if (v->read_only)
        fail(path.mark, "key '" + path.value + "': init refused, " +
                            VarRegistry::check_write(*v, nullptr) +
                            " (plcrun CONFIG --list-vars marks such variables read-only)");
      const std::string err = VarRegistry::write_text(*v, value.value);
      if (!err.empty()) fail(value.mark, "init of '" + path.value + "': " + err);
    }
  }
  for (auto& t : tasks_) {
    for (auto& ranges : t->bound) coalesce(ranges);
    for (io::Area a : {io::Area::Input, io::Area::Output, io::Area::Memory}) {
      std::uint8_t* img = t->image.area(a).data();
      std::uint8_t* glob = global_.area(a).data();
      std::uint8_t* before = t->before.area(a).data();
      for (const ImageRange& r : t->bound[static_cast<std::size_t>(a)]) {
        const std::size_t n = r.end - r.begin;
        t->copy_in.push_back({img + r.begin, glob + r.begin, nullptr, n});
        if (a == io::Area::Input) continue;
        t->keep.push_back({before + r.begin, img + r.begin, nullptr, n});
        t->copy_out.push_back({glob + r.begin, img + r.begin, nullptr, n});
        t->merge_out.push_back({glob + r.begin, img + r.begin, before + r.begin, n});
      }
    }
  }
  plan_device_io();  // again: TaskRuntime::plain_in and plain_out take copy_in and copy_out
  for (auto& d : devices_) d.link = &d.plugin->link(d.index);
  // Tasks run their programs in the order the task lists them.
  for (auto& t : tasks_) {
    std::vector<Program*> ordered;
    for (const auto& n : t->program_names) ordered.push_back(program(n));
    t->programs = ordered;
  }
  // Devices no FB drives: their outputs belong to the task that exchanges them.
  for (std::size_t i = 0; i < devices_.size(); ++i)
    if (!device_has_port[i])
      set_bits(tasks_[devices_[i].task]->owned_q, devices_[i].out.byte,
               devices_[i].sizes.output_bytes);

  // Safe values of outputs (default 0).
  for (const SafeValueConfig& sv : cfg.safe_values) {
    auto r = io::parse_iec_address(sv.address.value);
    if (!r.address) fail(sv.address.mark, "safe_values: " + r.error);
    if (r.address->area != io::Area::Output)
      fail(sv.address.mark, "safe_values: " + sv.address.value + " is not an output (%Q) address");
    if (!global_.contains(*r.address))
      fail(sv.address.mark, "safe_values: " + sv.address.value + " lies outside the output image");
    VarInfo v;
    v.type = r.address->size == io::AddrSize::Bit     ? VarType::BOOL
             : r.address->size == io::AddrSize::Byte  ? VarType::BYTE
             : r.address->size == io::AddrSize::Word  ? VarType::WORD
             : r.address->size == io::AddrSize::DWord ? VarType::DWORD
                                                      : VarType::LWORD;
    v.address = *r.address;
    v.image_ptr = safe_q_.data() + r.address->byte;
    v.order = order_;
    const std::string err = VarRegistry::write_text(v, sv.value.value);
    if (!err.empty()) fail(sv.value.mark, "safe_values " + sv.address.value + ": " + err);
  }
  // Outputs start at their safe values.
  std::copy(safe_q_.begin(), safe_q_.end(), global_.area(io::Area::Output).begin());
  for (auto& t : tasks_) t->image.copy_from(global_);

  for (auto& [_, p] : programs_) p->init();
}

io::Plugin* Runtime::plugin(const std::string& name) {
  for (auto& [n, p] : plugins_)
    if (n == name) return p.get();
  return nullptr;
}

Program* Runtime::program(const std::string& name) {
  for (auto& [n, p] : programs_)
    if (n == name) return p.get();
  return nullptr;
}

const TaskRuntime* Runtime::task(const std::string& name) const {
  for (const auto& t : tasks_)
    if (t->name == name) return t.get();
  return nullptr;
}

}  // namespace plc
