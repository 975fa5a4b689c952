#include "plc/debug/trace.hpp"

#include <algorithm>
#include <cstring>

#include "plc/debug/one_task.hpp"
#include "plc/detail/small_copy.hpp"
#include "plc/iec_literal.hpp"
#include "plc/thread_guard.hpp"

namespace plc::debug {
namespace {

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// VCD identifiers: short strings of printable characters.
std::string vcd_id(std::size_t i) {
  std::string id;
  do {
    id += static_cast<char>(33 + i % 94);
    i /= 94;
  } while (i);
  return id;
}

int vcd_width(VarType t) {
  switch (t) {
    case VarType::BOOL:
      return 1;
    case VarType::REAL:
    case VarType::LREAL:
      return 0;  // real
    default:
      return static_cast<int>(size_of(t) * 8);
  }
}

// The size_of(v.type) bytes that VarRegistry::read() reads: native
// storage, or v's bytes in the image.
const std::uint8_t* storage(const VarInfo& v) {
  return v.address ? v.image_ptr : static_cast<const std::uint8_t*>(v.ptr);
}

// A path component as a VCD identifier: brackets would read as bit selects.
std::string vcd_name(std::string s) {
  for (char& c : s)
    if (c == '[' || c == ']' || c == '%') c = '_';
  while (!s.empty() && s.back() == '_') s.pop_back();
  return s;
}

}  // namespace

std::string Trace::add(const std::string& p) {
  if (running()) return "stop the trace before changing it";
  Column c;
  if (!p.empty() && p[0] == '%') {
    auto r = io::parse_iec_address(p);
    if (!r.address) return r.error;
    if (!global_.contains(*r.address)) return p + " lies outside the image";
    static const VarType types[] = {VarType::BOOL, VarType::BYTE, VarType::WORD, VarType::DWORD,
                                    VarType::LWORD};
    c.var.path = r.address->to_string();
    c.var.type = types[static_cast<int>(r.address->size)];
    c.var.address = *r.address;
    c.var.image_ptr = global_.at(*r.address);
    c.var.order = order_;
  } else {
    const VarInfo* v = vars_.find(p);
    if (!v) return "unknown variable '" + p + "'";
    if (v->type == VarType::STRING) return "'" + p + "' is a STRING; traces hold numbers and bits";
    c.var = *v;
  }
  if (std::string err = one_task_check({&c.var}, true); !err.empty()) return err;
  columns_.push_back(std::move(c));
  return {};
}

std::string Trace::one_task_check(const std::vector<const VarInfo*>& extra,
                                  bool with_trigger) const {
  if (!one_task_) return {};
  std::vector<const VarInfo*> vars;
  for (const Column& c : columns_) vars.push_back(&c.var);
  if (with_trigger && trigger_)
    for (const VarInfo* v : trigger_->variables()) vars.push_back(v);
  vars.insert(vars.end(), extra.begin(), extra.end());
  return one_task_error(vars, one_task_names_);
}

bool Trace::reads_global() const {
  for (const Column& c : columns_)
    if (c.var.task < 0) return true;
  return trigger_ && trigger_->reads_global();
}

std::string Trace::set_trigger(const std::string& text) {
  if (running()) return "stop the trace before changing it";
  if (text.empty()) {
    trigger_.reset();
    return {};
  }
  std::string err;
  auto trigger = Condition::compile(text, vars_, global_, order_, err);
  if (!trigger) return err;
  if (err = one_task_check(trigger->variables(), false); !err.empty()) return err;
  trigger_ = std::move(trigger);
  return {};
}

int Trace::sampling_task(int fallback) const {
  for (const Column& c : columns_)
    if (c.var.task >= 0) return c.var.task;
  if (one_task_ && trigger_)
    for (const VarInfo* v : trigger_->variables())
      if (v->task >= 0) return v->task;
  return fallback;
}

std::string Trace::start(const std::string& file, std::optional<TraceFormat> format) {
  if (running()) return "the trace is already running (trace stop first)";
  if (columns_.empty()) return "no variables to trace (trace add PATH)";
  format_ = format ? *format : (ends_with(file, ".vcd") ? TraceFormat::Vcd : TraceFormat::Csv);
  file_ = std::fopen(file.c_str(), "w");
  if (!file_) return "cannot write '" + file + "'";
  file_name_ = file;
  plan_spans();
  const std::size_t slots = pre_rows_ + 1;
  meta_.assign(slots, {});
  raw_.assign(slots * row_bytes_, 0);
  last_.assign(columns_.size(), 0);
  have_last_ = false;
  ring_head_ = ring_count_ = 0;
  rows_sampled_ = overflow_blocks_ = 0;
  triggered_ = !trigger_;
  text_.clear();
  text_.reserve(1 << 16);
  write_header();
  flush_text();
  free_.clear();
  full_.clear();
  for (std::size_t i = 0; i < kBlocks; ++i) free_.push_back(new_block());
  cur_ = new_block();
  closing_ = false;
  error_.clear();
  // A failed writer fails the trace (error(): plcrun says FAILED, exit code
  // 1) and drains the blocks unwritten, so a sampler waiting for one
  // (backpressure) never hangs.
  writer_ = std::thread([this] {
    run_guarded(
        "trace writer", [this] { writer_loop(); },
        [this](std::string_view what) {
          std::unique_lock<std::mutex> lock(mu_);
          error_ = "the writer thread failed: " + std::string(what);
          for (;;) {
            for (auto& b : full_) {
              b->n = 0;
              free_.push_back(std::move(b));
            }
            full_.clear();
            cv_.notify_all();
            if (closing_) return;
            cv_.wait(lock, [this] { return closing_ || !full_.empty(); });
          }
        });
  });
  return {};
}

void Trace::write_header() {
  if (format_ == TraceFormat::Csv) {
    text_ += "time_ns,cycle";
    for (const Column& c : columns_) text_ += "," + c.var.path;
    text_ += "\n";
    return;
  }
  // No $date: two runs of the same cell must give identical files.
  text_ += "$version softplc trace $end\n$timescale 1ns $end\n";
  std::vector<std::string> open;  // current scope path
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    std::vector<std::string> parts;
    std::string path = columns_[i].var.path, part;
    for (char ch : path) {
      if (ch == '.') {
        parts.push_back(vcd_name(part));
        part.clear();
      } else {
        part += ch;
      }
    }
    const std::string leaf = vcd_name(part);
    std::size_t common = 0;
    while (common < open.size() && common < parts.size() && open[common] == parts[common]) ++common;
    while (open.size() > common) {
      text_ += "$upscope $end\n";
      open.pop_back();
    }
    for (std::size_t k = common; k < parts.size(); ++k) {
      text_ += "$scope module " + parts[k] + " $end\n";
      open.push_back(parts[k]);
    }
    const int w = vcd_width(columns_[i].var.type);
    if (w == 0) {
      text_ += "$var real 64 " + vcd_id(i) + " " + leaf + " $end\n";
    } else {
      text_ += std::string("$var ") + (w == 1 ? "wire" : "integer") + " " + std::to_string(w) +
               " " + vcd_id(i) + " " + leaf + " $end\n";
    }
  }
  while (!open.empty()) {
    text_ += "$upscope $end\n";
    open.pop_back();
  }
  text_ += "$enddefinitions $end\n";
}

// The columns' storage bytes as few spans as possible: sorted by address,
// overlapping or touching bytes merged (an array's elements, the bits of
// one image byte). Only bytes of traced variables are read, never a gap
// between them (it may belong to another object).
void Trace::plan_spans() {
  struct Piece {
    const std::uint8_t* src;
    std::size_t bytes;
    std::size_t column;
  };
  std::vector<Piece> pieces;
  for (std::size_t i = 0; i < columns_.size(); ++i)
    pieces.push_back({storage(columns_[i].var), size_of(columns_[i].var.type), i});
  std::sort(pieces.begin(), pieces.end(), [](const Piece& a, const Piece& b) {
    return std::less<const std::uint8_t*>()(a.src, b.src);
  });
  spans_.clear();
  column_at_.assign(columns_.size(), 0);
  row_bytes_ = 0;
  for (const Piece& p : pieces) {
    Span* s = spans_.empty() ? nullptr : &spans_.back();
    if (s && !std::less<const std::uint8_t*>()(s->src + s->bytes, p.src)) {
      const std::size_t end = std::size_t(p.src - s->src) + p.bytes;
      if (end > s->bytes) {
        row_bytes_ += end - s->bytes;
        s->bytes = end;
      }
    } else {
      spans_.push_back({p.src, p.bytes, row_bytes_});
      row_bytes_ += p.bytes;
      s = &spans_.back();
    }
    column_at_[p.column] = s->at + std::size_t(p.src - s->src);
  }
  // By size for capture(): the spans of 1, 2, 4 and 8 bytes (most are one
  // variable: BOOL, INT, REAL/DINT, LREAL/TIME) each copied as one load
  // and one store in a loop of their own, the rest after them. Each span
  // has its own bytes in the row, so their order does not matter.
  static constexpr std::size_t kSizes[] = {1, 2, 4, 8};
  std::vector<Span> by_size;
  for (std::size_t k = 0; k < 4; ++k) {
    for (const Span& s : spans_)
      if (s.bytes == kSizes[k]) by_size.push_back(s);
    size_end_[k] = by_size.size();
  }
  for (const Span& s : spans_)
    if (s.bytes != 1 && s.bytes != 2 && s.bytes != 4 && s.bytes != 8) by_size.push_back(s);
  spans_ = std::move(by_size);
  decode_.clear();
  for (const Column& c : columns_) decode_.push_back(c.var);
  values_.assign(columns_.size(), 0);
}

std::unique_ptr<Trace::Block> Trace::new_block() const {
  auto b = std::make_unique<Block>();
  b->meta.resize(kBlockRows);
  b->raw.resize(kBlockRows * row_bytes_);
  return b;
}

// Inline copies (a call into the library's memcpy per span cost more than
// the copy), without a test of the size per span for the spans of 1, 2, 4
// and 8 bytes (plan_spans() put them first, by size).
void Trace::capture(Row* meta, std::uint8_t* raw, const ScanContext& ctx) {
  *meta = {ctx.now.count(), ctx.cycle};
  const Span* s = spans_.data();
  const auto fixed = [&]<std::size_t K>(const Span* end) {
    for (; s != end; ++s) {
      unsigned char v[K];
      std::memcpy(v, s->src, K);
      std::memcpy(raw + s->at, v, K);
    }
  };
  fixed.template operator()<1>(spans_.data() + size_end_[0]);
  fixed.template operator()<2>(spans_.data() + size_end_[1]);
  fixed.template operator()<4>(spans_.data() + size_end_[2]);
  fixed.template operator()<8>(spans_.data() + size_end_[3]);
  for (const Span* end = spans_.data() + spans_.size(); s != end; ++s)
    ::plc::detail::copy_bytes(raw + s->at, s->src, s->bytes);
}

void Trace::append(const Row& m, const std::uint8_t* raw) {
  cur_->meta[cur_->n] = m;
  std::memcpy(cur_->raw.data() + cur_->n * row_bytes_, raw, row_bytes_);
  advance();
}

void Trace::advance() {
  if (++cur_->n == kBlockRows) hand_off();
  ++rows_sampled_;
}

void Trace::hand_off() {
  std::unique_lock<std::mutex> lock(mu_);
  full_.push_back(std::move(cur_));
  cv_.notify_one();
  if (backpressure_) cv_.wait(lock, [this] { return !free_.empty(); });
  if (!free_.empty()) {
    cur_ = std::move(free_.back());
    free_.pop_back();
  } else {
    ++overflow_blocks_;  // the writer is behind: grow rather than lose rows
    lock.unlock();
    cur_ = new_block();
    lock.lock();
  }
  cur_->n = 0;
  cv_.notify_one();
}

void Trace::sample(const ScanContext& ctx) {
  if (!running()) return;
  const std::size_t nb = row_bytes_;
  if (!triggered_) {
    const std::size_t slots = pre_rows_ + 1;
    const std::size_t slot = (ring_head_ + ring_count_) % slots;
    capture(&meta_[slot], raw_.data() + slot * nb, ctx);
    if (ring_count_ < slots)
      ++ring_count_;
    else
      ring_head_ = (ring_head_ + 1) % slots;
    if (trigger_ && trigger_->holds()) {
      triggered_ = true;
      for (std::size_t k = 0; k < ring_count_; ++k) {
        const std::size_t s = (ring_head_ + k) % slots;
        append(meta_[s], raw_.data() + s * nb);
      }
      ring_count_ = 0;
    }
    return;
  }
  capture(&cur_->meta[cur_->n], cur_->raw.data() + cur_->n * nb, ctx);
  advance();
}

void Trace::writer_loop() {
  std::unique_lock<std::mutex> lock(mu_);
  while (true) {
    cv_.wait(lock, [this] { return closing_ || !full_.empty(); });
    while (!full_.empty()) {
      std::unique_ptr<Block> b = std::move(full_.front());
      full_.pop_front();
      lock.unlock();
      for (std::size_t r = 0; r < b->n; ++r) format_row(b->meta[r], b->raw.data() + r * row_bytes_);
      flush_text();
      lock.lock();
      b->n = 0;
      free_.push_back(std::move(b));
      cv_.notify_all();  // a sampler may wait for a free block
    }
    if (closing_) return;
  }
}

void Trace::format_row(const Row& m, const std::uint8_t* bytes) {
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    VarInfo& d = decode_[i];
    auto* p = const_cast<std::uint8_t*>(bytes + column_at_[i]);  // only read
    if (d.address)
      d.image_ptr = p;
    else
      d.ptr = p;
    std::uint64_t v = 0;
    VarRegistry::read(d, &v);
    values_[i] = v;
  }
  const std::uint64_t* row = values_.data();
  if (format_ == TraceFormat::Csv) {
    text_ += std::to_string(m.time_ns);
    text_ += ',';
    text_ += std::to_string(m.cycle);
    for (std::size_t i = 0; i < columns_.size(); ++i) {
      text_ += ',';
      append_value(text_, columns_[i].var.type, &row[i]);
    }
    text_ += '\n';
    return;
  }
  bool stamped = false;
  for (std::size_t i = 0; i < columns_.size(); ++i) {
    if (have_last_ && last_[i] == row[i]) continue;
    if (!stamped) {
      text_ += '#';
      text_ += std::to_string(m.time_ns);
      text_ += '\n';
      stamped = true;
    }
    last_[i] = row[i];
    const VarType t = columns_[i].var.type;
    const int w = vcd_width(t);
    if (w == 1) {
      text_ += (row[i] & 1) ? '1' : '0';
    } else if (w == 0) {
      double d;
      if (t == VarType::REAL) {
        float f;
        std::memcpy(&f, &row[i], sizeof f);
        d = f;
      } else {
        std::memcpy(&d, &row[i], sizeof d);
      }
      char buf[48];
      std::snprintf(buf, sizeof buf, "r%.17g ", d);
      text_ += buf;
    } else {
      // Binary without leading zeros, as VCD allows.
      char buf[72];
      int n = 0;
      buf[n++] = 'b';
      const std::uint64_t v = w == 64 ? row[i] : row[i] & ((1ULL << w) - 1);
      const int top = v ? 63 - __builtin_clzll(v) : 0;
      for (int b = top; b >= 0; --b) buf[n++] = ((v >> b) & 1U) ? '1' : '0';
      buf[n++] = ' ';
      text_.append(buf, std::size_t(n));
    }
    text_ += vcd_id(i);
    text_ += '\n';
  }
  have_last_ = true;
  if (text_.size() > (1 << 16)) flush_text();
}

void Trace::flush_text() {
  if (file_ && !text_.empty()) std::fwrite(text_.data(), 1, text_.size(), file_);
  text_.clear();
}

void Trace::stop() {
  if (!file_) return;
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (cur_ && cur_->n) full_.push_back(std::move(cur_));
    closing_ = true;
  }
  cv_.notify_one();
  if (writer_.joinable()) writer_.join();
  flush_text();
  std::fclose(file_);
  file_ = nullptr;
}

std::string Trace::describe() const {
  std::string s = std::to_string(columns_.size()) + " variable(s)";
  for (const Column& c : columns_) s += " " + c.var.path;
  s += trigger_ ? "; trigger: " + trigger_->text() : "; no trigger";
  s += "; pre-trigger rows: " + std::to_string(pre_rows_);
  if (running())
    s += "; running into " + file_name_ +
         (triggered_ ? " (triggered, " : " (waiting for trigger, ") +
         std::to_string(rows_sampled_) + " rows)";
  else
    s += "; stopped";
  return s;
}

}  // namespace plc::debug
