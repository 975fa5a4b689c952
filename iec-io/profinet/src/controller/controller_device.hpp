// The controller's state of one device and its AR (controller.cpp), and the
// Connect request built from the device's description (connect_plan.cpp).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "plc/profinet/controller/connect_plan.hpp"
#include "plc/profinet/controller/controller.hpp"
#include "plc/profinet/wire/alarm.hpp"
#include "plc/profinet/wire/blocks.hpp"
#include "plc/profinet/wire/cyclic.hpp"

namespace plc::profinet {

enum class RpcCall : std::uint8_t { None, Connect, Write, PrmEnd, Read, RecordWrite, Release };

struct Controller::Device {
  ControllerDevice cfg;
  std::size_t index = 0;
  ArState state = ArState::Waiting;
  io::DeviceLink link;
  DeviceCounters counters;
  std::vector<std::uint8_t> in, out;  // user data (staging)
  std::string last_error;
  std::string last_alarm;
  TIME next_try{0};
  TIME deadline{0};  // of the present step (DCP, PrmEnd -> ApplicationReady)

  // DCP
  Mac mac{};
  std::uint32_t xid = 0;
  bool name_set = false;  // set_name done (once per run)

  // The AR
  Uuid ar_uuid;
  std::uint16_t session_key = 0;
  Uuid activity;
  std::uint32_t rpc_seq = 0;
  std::uint16_t record_seq = 0;
  ConnectPlan plan;
  std::uint16_t input_frame_id = 0, output_frame_id = 0;
  TIME interval{0};                // send interval of this AR (clock x its reduction ratio)
  std::uint16_t counter_step = 0;  // cycle counter per frame (31.25 us units)
  bool cyclic = false;             // output frames running
  bool app_ready = false;
  TIME next_send{0};
  std::uint16_t cycle_counter = 0;
  std::vector<std::uint8_t> tx;      // one output frame, its C_SDU kept in place between sends
  std::size_t tx_length = 0;         // its length once its header is written (0: cannot be built)
  std::span<std::uint8_t> tx_c_sdu;  // cyclic_c_sdu(tx, tx_c_sdu_length, true), set with tx
  std::size_t tx_c_sdu_length = 0;
  bool rx_seen = false;
  TIME last_input{0};
  std::uint16_t last_rx_counter = 0;
  TIME connected_at{0};

  // The one RPC call in flight
  RpcCall call = RpcCall::None;
  std::uint32_t call_seq = 0;
  TIME call_deadline{0};
  io::RecordRequest* record = nullptr;
  bool releasing = false;

  // Alarms, per priority (0 = low 0xFE01, 1 = high 0xFC01)
  std::uint16_t alarm_remote_ref = 0;
  std::uint16_t alarm_local_ref = 0;
  struct AlarmChannel {
    std::uint16_t send_seq = rta::kSeqInitial;  // our last DATA sent
    std::uint16_t rx_seq = rta::kSeqInitial;    // their last DATA taken
    bool ack_pending = false;                   // our AlarmAck not yet ACKed
    std::vector<std::uint8_t> ack_frame;        // to repeat
    TIME ack_deadline{0};
    int ack_tries = 0;
  };
  std::array<AlarmChannel, 2> alarm{};
};

}  // namespace plc::profinet
