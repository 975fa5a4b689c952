// The PROFINET codec in one include.
#pragma once

#include "plc/profinet/wire/alarm.hpp"
#include "plc/profinet/wire/blocks.hpp"
#include "plc/profinet/wire/codec.hpp"
#include "plc/profinet/wire/cyclic.hpp"
#include "plc/profinet/wire/dcp.hpp"
#include "plc/profinet/wire/ethernet.hpp"
#include "plc/profinet/wire/rpc.hpp"
