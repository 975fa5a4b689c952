// A program with RETAIN and PERSISTENT fields, built in two versions into
// cell libraries for the online change of retained programs (issue 21,
// KEEPER_VERSION):
//   1  count, twin (DINT, RETAIN), note (INT, RETAIN), level (REAL, RETAIN),
//      recipe (DINT, PERSISTENT), plain (DINT), a CTU kept whole (RETAIN);
//   2  note removed, level REAL -> LREAL, extra (LINT, RETAIN) added, plain
//      now RETAIN; the rest as in 1.
// Every scan counts: count and twin end each scan equal (a snapshot of one
// scan has them equal), and `build` says which code runs.
#include "plc/fb/iec/iec.hpp"
#include "plc/program.hpp"

using namespace plc;

class Keeper : public ProgramBase<Keeper> {
 public:
  DINT count = 0;
  DINT twin = 0;
#if KEEPER_VERSION == 1
  INT note = 42;
  REAL level = 1.5F;
#else
  LREAL level = 2.5;
  LINT extra = 5;
#endif
  DINT recipe = 7;
  DINT plain = 0;
  DINT build = KEEPER_VERSION;
  iec::CTU parts;

  void cycle(const ScanContext&) override {
    ++count;
    twin = count;
    ++plain;
    build = KEEPER_VERSION;
    parts(count % 2 == 0, false, 1000);
  }

#if KEEPER_VERSION == 1
  PLC_REFLECT(count, twin, note, level, recipe, plain, build, parts)
  PLC_RETAIN(count, twin, note, level, parts)
#else
  PLC_REFLECT(count, twin, level, extra, recipe, plain, build, parts)
  PLC_RETAIN(count, twin, level, extra, plain, parts)
#endif
  PLC_PERSISTENT(recipe)
};
PLC_REGISTER_PROGRAM(Keeper)
