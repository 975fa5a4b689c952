// Values as plcrun's shared memory holds them (native storage of their
// type, copied by a scan thread or read by the debugger), turned into what
// the bridge publishes: IEC text and numbers for plotting. Bytes from
// another process are never taken for more than they are: a BOOL is any
// byte (not 0 means TRUE), a STRING's length is clamped to its capacity.
#pragma once

#include <string>

#include "plc/types.hpp"

namespace plc::hmi {

// IEC notation (format_value): TRUE, 16#047F, T#20ms, 'text'.
std::string value_text(VarType t, const unsigned char* p);
// A number for trace_sample_t (NaN for STRING).
double value_number(VarType t, const unsigned char* p);

}  // namespace plc::hmi
