// The binary interface between plcrun and the cell libraries it loads
// (`libraries:` in a cell config). A cell library is C++ compiled against
// this runtime's headers: it derives from plc::Program, fills a
// plc::FieldVisitor, calls into the registries and the FB libraries. Any
// change to those classes' layout or to a signature they use changes the
// ABI. PLC_ABI_VERSION counts such changes; bump it in the same commit.
//
// softplc_add_cell_library() (cmake/softplc_cell_library.cmake) compiles
// PLC_CELL_LIBRARY_ABI() into every cell library; plcrun reads the symbol
// before it uses anything the library registered and refuses a library
// built against another version (plc/cell_library.hpp).
#pragma once

// 2: plc::io::DeviceLink holds the last alarm (issue 11) and its last state
// change (issue 13).
// 3: plc::io::ModelParams carries the config file's folder, which a
// relative file parameter is taken from (issue 21).
// 4: plc::io::Plugin records the failure of its thread (fail(), failed(),
// failure(): issue 21 follow-up).
// 5: plc::io::Plugin::direct_io() (a new virtual), DriveAxis holds
// program_commits_, FHostProtocol its CRC2 caches (issue 23).
// 6: plc::io::DeviceLink counts into its runtime's total of tracking links,
// PR5510_Device and NORD_SAFE_IO keep their decoded status per change,
// DriveAxis::begin() is inline (issue 23, second round).
// 7: TaskRuntime::merge_bits, the Recorder's whole_image() override;
// Crc2Cache's packed heads and number part, FHostProtocol::cycle() inline
// (so F_MODULE and NORD_SAFE_IO), the weighing blocks' inline members
// (issue 23, third round).
// 8: plc::io::SimDevice keeps its buffers as spans, Runtime's private
// scan_plain()/scan_hooked() split, FHostProtocol::cycle() a member template
// with a steady path, PR5510_Device's arbitration templates, Crc2Cache
// inline compare (issue 23, fourth round).
// 9: plc::io::DeviceLink points at its runtime's count of state changes
// (set_deferred's third argument), TaskRuntime::latched_changes and
// via_plugin as PluginDevice entries, the current owner as an inline
// thread_local (plc/io/current_owner.hpp), SimDevice::step_full(); the
// NORD model's and safety functions' caches; NORD_SAFE_IO's cached F-data,
// FHostProtocol::cycle() returning bool; MC_Power's, MC_Reset's and the
// move blocks' operator() inline (no longer exported by the drive library)
// (issue 23, fifth and sixth rounds).
// 10: inline steady paths in the block headers: MC_Power's, the MC blocks'
// one-load idle test, F_MODULE's steady_exchange()/steady_scan() with
// scan_general() (F_MODULE and NORD_SAFE_IO always inline),
// PR5510_Device's and PR5510_BatchWeigh's operator() inline; the NORD
// model's steady exchange and the PR5510 model's and FillingProcess's kept
// flags (issue 23, seventh to ninth rounds).
// 11: DeviceModel::answering() a kept flag (set_answering_now(), no longer
// virtual); TaskRuntime's plain-scan copy lists (plain_in, plain_out,
// plain_fused, any_via_plugin) and the timed-scan countdown; Runtime's
// alive-task count (issue 23, tenth round).
#define PLC_ABI_VERSION 11

// The exported symbol's name, for dlsym.
#define PLC_CELL_ABI_SYMBOL "softplc_cell_abi_version"

#define PLC_CELL_LIBRARY_ABI(version)                     \
  extern "C" __attribute__((visibility("default"), used)) \
  const unsigned softplc_cell_abi_version = (version);
