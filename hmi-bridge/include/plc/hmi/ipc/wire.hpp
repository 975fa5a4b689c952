// A small binary encoding for what plcrun writes into the shared memory for
// its HMI bridge (the cell layout, statistics, diagnostics): little-endian
// integers and length-prefixed strings. The reader checks every length
// against what is left and every string against a bound, so a torn or
// corrupt block decodes to "not ok", never to a read outside it.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace plc::hmi::ipc {

class WireOut {
 public:
  void u8(std::uint8_t v) { b_.push_back(v); }
  void u16(std::uint16_t v) { raw(&v, sizeof v); }
  void u32(std::uint32_t v) { raw(&v, sizeof v); }
  void u64(std::uint64_t v) { raw(&v, sizeof v); }
  void i64(std::int64_t v) { raw(&v, sizeof v); }
  void str(const std::string& s) {
    u32(std::uint32_t(s.size()));
    raw(s.data(), s.size());
  }
  [[nodiscard]] const std::vector<unsigned char>& bytes() const { return b_; }

 private:
  void raw(const void* p, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(p);
    b_.insert(b_.end(), c, c + n);
  }
  std::vector<unsigned char> b_;
};

class WireIn {
 public:
  WireIn(const unsigned char* p, std::size_t n) : p_(p), n_(n) {}
  std::uint8_t u8() { return get<std::uint8_t>(); }
  std::uint16_t u16() { return get<std::uint16_t>(); }
  std::uint32_t u32() { return get<std::uint32_t>(); }
  std::uint64_t u64() { return get<std::uint64_t>(); }
  std::int64_t i64() { return get<std::int64_t>(); }
  // At most `max` bytes; longer is a corrupt block.
  std::string str(std::size_t max = 1 << 16) {
    const std::uint32_t n = u32();
    if (!ok_ || n > max || n > n_ - pos_) {
      ok_ = false;
      return {};
    }
    std::string s(reinterpret_cast<const char*>(p_ + pos_), n);
    pos_ += n;
    return s;
  }
  // A count of elements that each take at least `min_bytes`: at most what
  // the rest of the block can hold.
  std::uint32_t count(std::size_t min_bytes) {
    const std::uint32_t n = u32();
    if (!ok_ || min_bytes == 0 || n > (n_ - pos_) / min_bytes) {
      ok_ = false;
      return 0;
    }
    return n;
  }
  [[nodiscard]] bool ok() const { return ok_; }
  [[nodiscard]] bool at_end() const { return ok_ && pos_ == n_; }
  void fail() { ok_ = false; }

 private:
  template <class T>
  T get() {
    T v{};
    if (!ok_ || sizeof v > n_ - pos_) {
      ok_ = false;
      return v;
    }
    std::memcpy(&v, p_ + pos_, sizeof v);
    pos_ += sizeof v;
    return v;
  }
  const unsigned char* p_;
  std::size_t n_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace plc::hmi::ipc
