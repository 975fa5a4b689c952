// Real time: which variables a breakpoint condition, a `run until`
// condition or a trace may read (issue 10, point 4).
//
// They are evaluated (sampled) on the scan thread of one task, right after
// its scan: that task's variables are then settled and read directly, and
// the global image (%I/%Q/%M addresses) is read under the image lock, so a
// row or a condition sees one consistent state. A variable of another task
// is written by that task's own thread at the same time: reading it would
// race and could mix two of its scans, or show a torn value. So in real
// time every program variable (located or not) in one condition or one
// trace must belong to the same task; addresses may be added freely.
// Virtual time has no such limit (the scans run one after another).
#pragma once

#include <string>
#include <vector>

#include "plc/var_registry.hpp"

namespace plc::debug {

// "" when every variable of `vars` that belongs to a task belongs to the
// same one; else why not, naming two variables and their tasks.
std::string one_task_error(const std::vector<const VarInfo*>& vars,
                           const std::vector<std::string>& task_names);

}  // namespace plc::debug
