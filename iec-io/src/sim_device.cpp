#include "plc/io/sim_device.hpp"

#include <algorithm>
#include <array>

namespace plc::io {

SimDevice::SimDevice(std::unique_ptr<DeviceModel> model)
    : model_(std::move(model)),
      inputs_(model_->input_size(), 0),
      outputs_(model_->output_size(), 0),
      silent_sink_(model_->input_size(), 0),
      from_plc_(outputs_),
      to_plc_(inputs_),
      silent_(silent_sink_) {
  link_.set_state(model_->answering() ? DeviceState::Online : DeviceState::Offline);
}

void SimDevice::step_full(TIME now, TIME dt) {
  const bool down = link_down(now);
  if (link_.maybe_queued()) serve_records(!down);
  if (down) {
    step_cut(now, dt);
    return;
  }
  was_down_ = false;
  step_up(now, dt);
}

void SimDevice::serve_records(bool reachable) {
  if (!link_.maybe_queued()) return;  // the usual step: nothing asked
  while (RecordRequest* r = link_.pop()) {
    if (!reachable || !model_->answering()) {
      r->fail(RecordError::NotReachable);
      continue;
    }
    if (r->kind() == RecordKind::Write) {
      const RecordError e = model_->write_record(r->index(), r->data());
      if (e == RecordError::None) {
        r->complete(r->data().size());
      } else {
        r->fail(e, static_cast<std::uint16_t>(e));
      }
    } else {
      // The request bytes share the answer's buffer: copy them out first.
      std::array<std::uint8_t, kRecordMaxBytes> request{};
      const auto req = r->data();
      std::copy(req.begin(), req.end(), request.begin());
      std::size_t len = 0;
      const RecordError e =
          model_->query_record(r->index(), {request.data(), req.size()}, r->buffer(), len);
      if (e == RecordError::None) {
        r->complete(len);
      } else {
        r->fail(e, static_cast<std::uint16_t>(e));
      }
    }
  }
}

// The cut link: no new request reaches the model, no answer the PLC.
void SimDevice::step_cut(TIME now, TIME dt) {
  if (!was_down_) outputs_at_cut_ = outputs_;
  was_down_ = true;
  model_->step(now, dt, outputs_at_cut_, silent_sink_);
  link_.set_state(DeviceState::Offline);
}

}  // namespace plc::io
