// One PROFIdrive parameter request in flight (spec §6.4): the request is
// written with a record Write on the parameter record index, then the
// response is fetched with a record Read on the same index; a Read refused
// because the response is not ready yet (InvalidState/DeviceBusy) is
// retried until the timeout. The response is matched to the request by the
// request reference (1..255, a new one per request) and the response ID.
// Nothing here blocks or allocates: poll() once per scan.
#pragma once

#include <cstdint>

#include "plc/fb/drive/diag_codes.hpp"
#include "plc/fb/drive/parameter_channel.hpp"
#include "plc/io/device_port.hpp"
#include "plc/io/record_request.hpp"
#include "plc/reflect.hpp"
#include "plc/types.hpp"

namespace plc::drive {

class ParamClient {
 public:
  enum class State : std::uint8_t { Idle, Writing, Reading, Done, Error };

  // Sends `r` (its reference is replaced by the next one). False (and state
  // Error) if the request could not be queued.
  bool start(io::DevicePort& port, std::uint16_t record_index, const ParamRequest& r, TIME now,
             TIME timeout);
  void poll(io::DevicePort& port, TIME now);
  void reset() {
    state_ = State::Idle;
    rec_.reset();
  }

  [[nodiscard]] State state() const { return state_; }
  [[nodiscard]] bool busy() const { return state_ == State::Writing || state_ == State::Reading; }
  [[nodiscard]] std::uint16_t error() const { return error_; }
  [[nodiscard]] const ParamResponse& response() const { return resp_; }
  [[nodiscard]] const ParamRequest& request() const { return req_; }

  // In-progress state (the request and response bodies of a request in
  // flight are not included: an acyclic request cannot be resumed anyway).
  PLC_REFLECT(state_, error_, index_, next_ref_, t0_, timeout_)
  PLC_INTERNAL(state_, error_, index_, next_ref_, t0_, timeout_)

 private:
  void fail(std::uint16_t e) {
    error_ = e;
    state_ = State::Error;
  }
  void check_response();

  io::RecordRequest rec_;
  ParamRequest req_;
  ParamResponse resp_;
  State state_ = State::Idle;
  std::uint16_t error_ = 0;
  std::uint16_t index_ = kParamRecordIndex;
  std::uint8_t next_ref_ = 1;
  TIME t0_{}, timeout_{};
};

// Helpers for single values.
ParamRequest make_read(std::uint16_t pnu, std::uint16_t subindex = 0, std::uint8_t elements = 0);
ParamRequest make_write(std::uint16_t pnu, std::uint8_t format, double value,
                        std::uint16_t subindex = 0);

}  // namespace plc::drive
