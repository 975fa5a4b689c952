// The program API: a program is a C++ class with FB members and a cycle
// body, registered by name so the cell config can instantiate it.
//
//   class Conveyor : public plc::ProgramBase<Conveyor> {
//    public:
//     plc::io::Located<plc::BOOL> start{"%IX0.0"};
//     plc::io::Located<plc::BOOL> motor{"%QX0.0"};
//     plc::iec::TON run_on;
//     void cycle(const plc::ScanContext& ctx) override {
//       run_on(ctx, start, T#5s);
//       motor = start || run_on.Q;
//     }
//     PLC_REFLECT(start, motor, run_on)
//   };
//   PLC_REGISTER_PROGRAM(Conveyor)
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "plc/field_visitor.hpp"
#include "plc/reflect.hpp"
#include "plc/scan_context.hpp"

namespace plc {

class Program {
 public:
  virtual ~Program() = default;
  // Once after binding, before the first scan (cold start initialisation).
  virtual void init() {}
  // The cycle body: called once per scan of the task that runs the program.
  virtual void cycle(const ScanContext& ctx) = 0;
  // Lists the fields (implemented by ProgramBase from PLC_REFLECT).
  virtual void describe(FieldVisitor& v) = 0;
};

template <class Self>
class ProgramBase : public Program {
 public:
  void describe(FieldVisitor& v) override { static_cast<Self*>(this)->reflect(v); }
};

using ProgramFactory = std::function<std::unique_ptr<Program>()>;

class ProgramRegistry {
 public:
  static ProgramRegistry& instance();
  void add(const std::string& type, ProgramFactory f);
  [[nodiscard]] const ProgramFactory* find(const std::string& type) const;
  [[nodiscard]] std::vector<std::string> names() const;
  // While a cell library loads, its registrations are collected here
  // instead of taking effect (plc/cell_library.hpp): they count only once
  // its ABI version has been checked. nullptr: add() registers.
  void set_capture(std::map<std::string, ProgramFactory>* c) { capture_ = c; }

 private:
  std::map<std::string, ProgramFactory> factories_;
  std::map<std::string, ProgramFactory>* capture_ = nullptr;
};

// Registers a program class under its own name. Put it in a .cpp that is
// part of an OBJECT library (see programs/CMakeLists.txt).
#define PLC_REGISTER_PROGRAM(Class)                                                           \
  namespace {                                                                                 \
  const bool plc_program_registered_##Class = [] {                                            \
    ::plc::ProgramRegistry::instance().add(#Class, [] { return std::make_unique<Class>(); }); \
    return true;                                                                              \
  }();                                                                                        \
  }

}  // namespace plc
