// The scan thread's current owner (DeviceLink::set_current_owner): the task
// whose scan runs, so that a request submitted now is delivered at that
// task's next latch. Only for the runtime's scan, which sets it twice per
// scan: inline there, a store instead of a call through the PLT into the io
// library. Everyone else calls DeviceLink::set_current_owner().
//
// Initial-exec: the general-dynamic model of a shared library would make
// each access a call to __tls_get_addr. The io library (which defines it)
// and the runtime are loaded with the program, never dlopen'ed on their own.
// constinit: a constant initializer, so no TLS wrapper function either.
#pragma once

namespace plc::io::detail {

extern constinit thread_local int tl_current_owner __attribute__((tls_model("initial-exec")));

inline void set_current_owner(int owner) { tl_current_owner = owner; }

}  // namespace plc::io::detail
