// CIP object classes and attribute ids the scanner and the slave use
// (toyo-vf66-devicenet.md §2 and §12 [std]).
#pragma once

#include <cstdint>

namespace plc::devicenet {

inline constexpr std::uint8_t kClassIdentity = 0x01;
inline constexpr std::uint8_t kClassMessageRouter = 0x02;
inline constexpr std::uint8_t kClassDeviceNet = 0x03;
inline constexpr std::uint8_t kClassAssembly = 0x04;
inline constexpr std::uint8_t kClassConnection = 0x05;

// Allocation choice bits (Allocate/Release_Master/Slave_Connection_Set).
inline constexpr std::uint8_t kAllocExplicit = 0x01;
inline constexpr std::uint8_t kAllocPoll = 0x02;
inline constexpr std::uint8_t kAllocBitStrobe = 0x04;
inline constexpr std::uint8_t kAllocMulticastPoll = 0x08;
inline constexpr std::uint8_t kAllocCos = 0x10;
inline constexpr std::uint8_t kAllocCyclic = 0x20;
inline constexpr std::uint8_t kAllocAckSuppression = 0x40;
inline constexpr std::uint8_t kUnallocated = 0xFF;  // master MAC of a free slave

// Predefined connection instances of the Connection object.
inline constexpr std::uint8_t kConnExplicit = 1;
inline constexpr std::uint8_t kConnPoll = 2;
// Connection object attributes.
inline constexpr std::uint8_t kConnAttrState = 1;
inline constexpr std::uint8_t kConnAttrProducedSize = 7;
inline constexpr std::uint8_t kConnAttrConsumedSize = 8;
inline constexpr std::uint8_t kConnAttrEpr = 9;
inline constexpr std::uint8_t kConnAttrWatchdogAction = 12;
// Connection states (attribute 1).
inline constexpr std::uint8_t kConnNonExistent = 0;
inline constexpr std::uint8_t kConnConfiguring = 1;
inline constexpr std::uint8_t kConnEstablished = 3;
inline constexpr std::uint8_t kConnTimedOut = 4;
inline constexpr std::uint8_t kConnDeferredDelete = 5;
// The predefined explicit connection's default expected packet rate.
inline constexpr std::uint16_t kDefaultExplicitEprMs = 2500;
// A connection times out after this many expected packet intervals.
inline constexpr int kTimeoutMultiplier = 4;

}  // namespace plc::devicenet
