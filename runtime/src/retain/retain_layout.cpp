#include "plc/retain/retain_layout.hpp"

#include <cstring>

namespace plc::retain {

std::size_t Layout::stored_size(VarType t) {
  return t == VarType::STRING ? 1 + STRING::capacity : size_of(t);
}

Layout::Layout(const VarRegistry& vars, const RetainConfig& cfg, io::ProcessImage& global)
    : global_(&global) {
  for (const VarInfo& v : vars.all()) {
    if (v.retain == RetainClass::None) continue;
    Entry e{};
    e.path = v.path;
    e.type = static_cast<std::uint8_t>(v.type);
    e.cls = v.retain;
    e.size = stored_size(v.type);
    e.var = v;
    e.task = v.task;
    if (v.address) {
      // Read and restored in the global image, under its lock (the task's
      // private copy is overwritten by the next copy-in).
      e.var.image_ptr = global.at(*v.address);
      e.task = -1;
    }
    entries_.push_back(std::move(e));
  }
  for (const RetainMemoryRange& r : cfg.memory) {
    Entry e{};
    e.path = "%MB" + std::to_string(r.byte) + "..%MB" + std::to_string(r.byte + r.count - 1);
    e.type = kMemoryBytes;
    e.size = r.count;
    e.mem_byte = r.byte;
    entries_.push_back(std::move(e));
  }
  std::uint64_t h = 1469598103934665603ULL;  // FNV-1a
  auto mix = [&h](unsigned char c) { h = (h ^ c) * 1099511628211ULL; };
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    Entry& e = entries_[i];
    // Natural alignment, so that an array's elements stay neighbours.
    const std::size_t align = e.size >= 8 ? 8 : e.size >= 4 ? 4 : e.size >= 2 ? 2 : 1;
    bytes_ = (bytes_ + align - 1) & ~(align - 1);
    e.offset = bytes_;
    bytes_ += e.size;
    const bool plain = e.type != kMemoryBytes && !e.var.address && e.var.type != VarType::STRING;
    if (!plain) {
      others_.push_back(i);
    } else if (const auto* src = static_cast<const std::uint8_t*>(e.var.ptr);
               !runs_.empty() && runs_.back().task == e.task &&
               runs_.back().src + runs_.back().n == src &&
               runs_.back().dst + runs_.back().n == e.offset) {
      runs_.back().n += e.size;
    } else {
      runs_.push_back({src, e.offset, e.size, e.task});
    }
    for (unsigned char c : e.path) mix(c);
    mix(0);
    mix(e.type);
    for (int i = 0; i < 4; ++i) mix(static_cast<unsigned char>(e.size >> (8 * i)));
  }
  hash_ = h;
}

void Layout::capture(int task, bool image, std::span<std::uint8_t> snapshot) const {
  for (const Run& r : runs_)
    if (task < 0 || r.task == task) std::memcpy(snapshot.data() + r.dst, r.src, r.n);
  for (std::size_t i : others_) {
    const Entry& e = entries_[i];
    std::uint8_t* dst = snapshot.data() + e.offset;
    if (e.type == kMemoryBytes) {
      if (image) std::memcpy(dst, global_->area(io::Area::Memory).data() + e.mem_byte, e.size);
      continue;
    }
    // Located %M variables live in the global image; plain ones in their task.
    if (e.task < 0 ? !image : (task >= 0 && e.task != task)) continue;
    if (e.var.type == VarType::STRING) {
      const STRING& s = *static_cast<const STRING*>(e.var.ptr);
      std::memset(dst, 0, e.size);
      dst[0] = static_cast<std::uint8_t>(s.size());
      std::memcpy(dst + 1, s.c_str(), s.size());
    } else {
      VarRegistry::read(e.var, dst);
    }
  }
}

void Layout::restore(const Entry& e, const std::uint8_t* value) const {
  if (e.type == kMemoryBytes) {
    std::memcpy(global_->area(io::Area::Memory).data() + e.mem_byte, value, e.size);
  } else if (e.var.type == VarType::STRING) {
    const std::size_t n = value[0] < STRING::capacity ? value[0] : STRING::capacity;
    *static_cast<STRING*>(e.var.ptr) =
        std::string_view(reinterpret_cast<const char*>(value) + 1, n);
  } else if (e.var.type == VarType::BOOL) {
    const bool b = value[0] != 0;  // any other byte than 0/1 is not a bool
    VarRegistry::write(e.var, &b);
  } else {
    VarRegistry::write(e.var, value);
  }
}

}  // namespace plc::retain
