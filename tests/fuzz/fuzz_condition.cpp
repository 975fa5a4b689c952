// Fuzz target: the condition parser of breakpoints and trace triggers
// (plc/debug/condition.hpp) over the filling cell's registry, then one
// evaluation. A text either compiles or fails with an error message; the
// evaluation of whatever compiles never faults (division by zero, overflow).
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "fuzz_cell.hpp"
#include "plc/debug/condition.hpp"
#include "plc/runtime.hpp"

namespace {
// A cell 200 scans in, so the variables hold values other than their
// initial ones.
plc::Runtime& cell() {
  static const std::unique_ptr<plc::Runtime> rt = [] {
    auto r = std::make_unique<plc::Runtime>(plc::fuzz::filling_cell());
    r->start(plc::io::ClockMode::Virtual);
    for (int i = 0; i < 200; ++i) r->tick();
    return r;
  }();
  return *rt;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  plc::Runtime& rt = cell();
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::string error;
  const auto c =
      plc::debug::Condition::compile(text, rt.vars(), rt.image(), rt.byte_order(), error);
  if (c) {
    (void)c->evaluate();
  } else if (error.empty()) {
    __builtin_trap();  // a refused condition must say why
  }
  return 0;
}
