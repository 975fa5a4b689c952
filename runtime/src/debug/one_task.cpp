#include "plc/debug/one_task.hpp"

namespace plc::debug {

std::string one_task_error(const std::vector<const VarInfo*>& vars,
                           const std::vector<std::string>& task_names) {
  const VarInfo* first = nullptr;
  auto name = [&task_names](int task) {
    return task >= 0 && std::size_t(task) < task_names.size() ? task_names[std::size_t(task)]
                                                              : std::to_string(task);
  };
  for (const VarInfo* v : vars) {
    if (v->task < 0) continue;
    if (!first) {
      first = v;
    } else if (v->task != first->task) {
      return "in real time the variables must belong to one task: " + first->path +
             " belongs to task '" + name(first->task) + "', " + v->path + " to task '" +
             name(v->task) +
             "' (each is read on its own task's thread right after that task's scan; "
             "%I/%Q/%M addresses may be used with either)";
    }
  }
  return {};
}

}  // namespace plc::debug
