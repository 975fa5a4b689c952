// All IEC 61131-3 standard function blocks and selection functions.
#pragma once

#include "plc/fb/iec/bistables.hpp"
#include "plc/fb/iec/counters.hpp"
#include "plc/fb/iec/edges.hpp"
#include "plc/fb/iec/selection.hpp"
#include "plc/fb/iec/tof.hpp"
#include "plc/fb/iec/ton.hpp"
#include "plc/fb/iec/tp.hpp"
