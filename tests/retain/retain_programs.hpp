// Programs with RETAIN / PERSISTENT fields for the retain tests and the crash
// test (registered by name).
#pragma once

#include "plc/fb/iec/iec.hpp"
#include "plc/io/located.hpp"
#include "plc/program.hpp"

namespace retaintest {

using namespace plc;

// An FB that declares one field RETAIN itself.
struct Learner {
  DINT scratch = 1;  // not retained
  REAL learned = 2;  // RETAIN by its own declaration
  PLC_REFLECT(scratch, learned)
  PLC_RETAIN(learned)
};

// Counts every scan into fields of every retain class.
class RetainProbe : public ProgramBase<RetainProbe> {
 public:
  DINT counter = 0;               // RETAIN
  DINT persist = 0;               // PERSISTENT
  DINT plain = 0;                 // neither
  STRING label = "init";          // RETAIN
  iec::CTU parts;                 // RETAIN, the whole instance
  Learner own;                    // unclassed: own.learned by the block's declaration
  Learner kept;                   // PERSISTENT: both fields, whatever Learner says
  io::Located<DINT> mem{"%MD8"};  // RETAIN, located in %M
  void cycle(const ScanContext&) override {
    ++counter;
    ++persist;
    ++plain;
    label = "scanned";
    parts(counter % 2 == 0, false, 1000);
    own.scratch += 1;
    own.learned += 1;
    kept.scratch += 1;
    kept.learned += 1;
    mem = mem + 1;
  }
  PLC_REFLECT(counter, persist, plain, label, parts, own, kept, mem)
  PLC_RETAIN(counter, label, parts, mem)
  PLC_PERSISTENT(persist, kept)
};

// RetainProbe after a program change: `counter` renamed to `count`,
// `persist` now LINT, `label` removed, `extra` added.
class RetainProbeV2 : public ProgramBase<RetainProbeV2> {
 public:
  DINT count = 0;
  LINT persist = 0;
  DINT plain = 0;
  DINT extra = 7;
  iec::CTU parts;
  Learner own;
  Learner kept;
  io::Located<DINT> mem{"%MD8"};
  void cycle(const ScanContext&) override {}
  PLC_REFLECT(count, persist, plain, extra, parts, own, kept, mem)
  PLC_RETAIN(count, extra, parts, mem)
  PLC_PERSISTENT(persist, kept)
};

// A retained %Q: refused when the cell is built.
class RetainedOutput : public ProgramBase<RetainedOutput> {
 public:
  io::Located<INT> out{"%QW0"};
  void cycle(const ScanContext&) override {}
  PLC_REFLECT(out)
  PLC_RETAIN(out)
};

}  // namespace retaintest
