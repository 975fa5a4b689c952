#include "plc/hmi/ipc/cell_layout.hpp"

#include "plc/hmi/ipc/layout.hpp"
#include "plc/hmi/ipc/wire.hpp"

namespace plc::hmi::ipc {

namespace {

constexpr std::size_t kMaxName = 4096;

void put_address(WireOut& w, const std::optional<io::IecAddress>& a) {
  w.u8(a ? 1 : 0);
  w.u8(a ? std::uint8_t(a->area) : 0);
  w.u8(a ? std::uint8_t(a->size) : 0);
  w.u8(a ? a->bit : 0);
  w.u32(a ? a->byte : 0);
}

bool get_address(WireIn& r, std::optional<io::IecAddress>& out) {
  const std::uint8_t has = r.u8(), area = r.u8(), size = r.u8(), bit = r.u8();
  const std::uint32_t byte = r.u32();
  if (!r.ok() || has > 1) return false;
  if (!has) return true;
  if (area > std::uint8_t(io::Area::Memory) || size > std::uint8_t(io::AddrSize::LWord) || bit > 7)
    return false;
  out = io::IecAddress{io::Area(area), io::AddrSize(size), byte, bit};
  return true;
}

}  // namespace

std::vector<unsigned char> CellLayout::encode() const {
  WireOut w;
  w.str(cell);
  w.u64(layout_hash);
  w.u32(image_input);
  w.u32(image_output);
  w.u32(image_memory);
  w.u32(std::uint32_t(tasks.size()));
  for (const Task& t : tasks) {
    w.str(t.name);
    w.i64(t.period_ns);
  }
  w.u32(std::uint32_t(devices.size()));
  for (const Device& d : devices) {
    w.str(d.name);
    w.str(d.plugin);
    w.str(d.input);
    w.str(d.output);
    w.u32(std::uint32_t(d.task));
    w.u32(std::uint32_t(d.in_bytes));
    w.u32(std::uint32_t(d.out_bytes));
  }
  w.u32(std::uint32_t(vars.size()));
  for (const Var& v : vars) {
    w.str(v.path);
    w.u8(std::uint8_t(v.type));
    put_address(w, v.address);
    w.u32(std::uint32_t(v.task));
    w.u8(std::uint8_t(v.published | v.writable << 1 | v.forceable << 2 | v.read_only << 3));
  }
  w.u32(std::uint32_t(slots.size()));
  for (const Slot& s : slots) {
    w.u32(s.task);
    w.u64(s.header);
    w.u64(s.buffer);
    w.u64(s.buffer_size);
    w.u32(std::uint32_t(s.items.size()));
    for (const Item& it : s.items) {
      w.u32(it.var);
      w.u32(it.offset);
    }
  }
  w.u32(std::uint32_t(start_alarms.size()));
  for (const Alarm& a : start_alarms) {
    w.str(a.kind);
    w.str(a.source);
    w.str(a.text);
    w.i64(a.utime);
  }
  return w.bytes();
}

std::optional<CellLayout> CellLayout::decode(const unsigned char* p, std::size_t n,
                                             std::size_t region_size, std::string& error) {
  WireIn r(p, n);
  CellLayout l;
  auto bad = [&error](const std::string& why) -> std::optional<CellLayout> {
    error = "cell layout: " + why;
    return std::nullopt;
  };
  l.cell = r.str(kMaxName);
  l.layout_hash = r.u64();
  l.image_input = r.u32();
  l.image_output = r.u32();
  l.image_memory = r.u32();
  l.tasks.resize(r.count(12));
  for (Task& t : l.tasks) {
    t.name = r.str(kMaxName);
    t.period_ns = r.i64();
  }
  l.devices.resize(r.count(28));
  for (Device& d : l.devices) {
    d.name = r.str(kMaxName);
    d.plugin = r.str(kMaxName);
    d.input = r.str(kMaxName);
    d.output = r.str(kMaxName);
    d.task = std::int32_t(r.u32());
    d.in_bytes = std::int32_t(r.u32());
    d.out_bytes = std::int32_t(r.u32());
    if (d.task < -1 || d.task >= std::int32_t(l.tasks.size())) return bad("a device's task");
  }
  l.vars.resize(r.count(18));
  for (Var& v : l.vars) {
    v.path = r.str(kMaxName);
    const std::uint8_t type = r.u8();
    if (type >= kVarTypes) return bad("a variable's type");
    v.type = VarType(type);
    if (!get_address(r, v.address)) return bad("a variable's address");
    v.task = std::int32_t(r.u32());
    if (v.task < -1 || v.task >= std::int32_t(l.tasks.size())) return bad("a variable's task");
    const std::uint8_t f = r.u8();
    v.published = f & 1;
    v.writable = f & 2;
    v.forceable = f & 4;
    v.read_only = f & 8;
  }
  l.slots.resize(r.count(32));
  for (Slot& s : l.slots) {
    s.task = r.u32();
    s.header = r.u64();
    s.buffer = r.u64();
    s.buffer_size = r.u64();
    if (s.task >= l.tasks.size()) return bad("a slot's task");
    if (s.header > region_size || region_size - s.header < sizeof(SlotHeader) ||
        s.buffer > region_size || region_size - s.buffer < s.buffer_size || s.header % 8 ||
        s.buffer % 8)
      return bad("a slot outside the region");
    s.items.resize(r.count(8));
    for (Item& it : s.items) {
      it.var = r.u32();
      it.offset = r.u32();
      if (it.var >= l.vars.size()) return bad("an item's variable");
      const VarType t = l.vars[it.var].type;
      const std::size_t size = t == VarType::STRING ? sizeof(STRING) : size_of(t);
      if (it.offset > s.buffer_size || s.buffer_size - it.offset < size)
        return bad("an item outside its buffer");
    }
  }
  l.start_alarms.resize(r.count(20));
  for (Alarm& a : l.start_alarms) {
    a.kind = r.str(kMaxName);
    a.source = r.str(kMaxName);
    a.text = r.str(kMaxName);
    a.utime = r.i64();
  }
  if (!r.at_end()) return bad("truncated or with bytes left over");
  return l;
}

std::optional<std::uint32_t> CellLayout::find(const std::string& path) const {
  for (std::size_t i = 0; i < vars.size(); ++i)
    if (vars[i].path == path) return std::uint32_t(i);
  return std::nullopt;
}

bool CellLayout::inside_image(const io::IecAddress& a) const {
  const std::uint32_t size = a.area == io::Area::Input    ? image_input
                             : a.area == io::Area::Output ? image_output
                                                          : image_memory;
  const std::uint64_t end = std::uint64_t(a.byte) + a.width_bytes();
  return end <= size;
}

}  // namespace plc::hmi::ipc
