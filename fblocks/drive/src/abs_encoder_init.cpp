#include "plc/fb/drive/abs_encoder_init.hpp"

namespace plc::drive {

namespace {
enum : INT { kIdle = 0, kDisable = 1, kWrite = 2, kPoll = 3, kReset = 4, kWaitBack = 5, kDone = 6 };
}

void AbsEncoderInit::operator()(const ScanContext& ctx, DriveAxis& axis) {
  axis.begin(ctx);
  const bool edge = Execute && !prev_execute_;
  prev_execute_ = Execute;
  auto finish_error = [&](std::uint16_t e) {
    Error = true;
    ErrorID = e;
    Busy = false;
    Step = kIdle;
    axis.InhibitPower = false;
    client_.reset();
  };
  auto go = [&](INT step) {
    Step = step;
    t0_ = ctx.now;
  };
  const bool timed_out = ctx.now - t0_ > Timeout;
  if (!Execute && !Busy) {
    Done = Error = false;
    ErrorID = 0;
  }
  if (edge && !Busy) {
    Done = Error = false;
    ErrorID = 0;
    Status = 0;
    seen_running_ = seen_offline_ = false;
    if (axis.CommError) {
      finish_error(axis.CommError);
    } else if (axis.operation_enabled() && !AllowDisable) {
      finish_error(kErrAbsEnabled);
    } else {
      Busy = true;
      axis.InhibitPower = true;
      go(kDisable);
    }
  }
  if (!Busy) {
    axis.block_done();
    return;
  }
  const bool pulses = (axis.ZSW2 & Zsw2::kPulsesEnabled) != 0 || axis.operation_enabled();
  switch (Step) {
    case kDisable:
      if (!pulses && axis.CommOk) {
        go(kWrite);
        client_.start(axis.Port, RecordIndex, make_write(kPnuAbsEncoderInit, 0x04, 1), ctx.now,
                      Timeout);
      } else if (timed_out) {
        finish_error(kErrAbsDisableTimeout);
      }
      break;
    case kWrite:
      client_.poll(axis.Port, ctx.now);
      if (client_.state() == ParamClient::State::Error) {
        finish_error(client_.error());
      } else if (client_.state() == ParamClient::State::Done) {
        go(kPoll);
        client_.start(axis.Port, RecordIndex, make_read(kPnuAbsEncoderInit), ctx.now, Timeout);
      }
      break;
    case kPoll:
      client_.poll(axis.Port, ctx.now);
      if (client_.state() == ParamClient::State::Error) {
        finish_error(client_.error());
      } else if (client_.state() == ParamClient::State::Done) {
        Status = static_cast<INT>(
            raw_to_double(client_.response().values[0], client_.response().format));
        if (Status == 4) {
          go(kReset);
          client_.start(axis.Port, RecordIndex, make_write(kPnuResetDrive, 0x03, 1), ctx.now,
                        Timeout);
        } else if (Status == 16) {
          finish_error(kErrAbsRefused);
        } else if (Status == 32) {
          finish_error(kErrAbsFailed);
        } else {
          if (Status == 2) seen_running_ = true;
          if (timed_out)
            finish_error(seen_running_ || Status == 2 ? kErrAbsRunningTimeout
                                                      : kErrAbsNoStartTimeout);
          else
            client_.start(axis.Port, RecordIndex, make_read(kPnuAbsEncoderInit), ctx.now, Timeout);
        }
      }
      break;
    case kReset:
      client_.poll(axis.Port, ctx.now);
      if (!axis.Port.online()) seen_offline_ = true;
      if (client_.state() == ParamClient::State::Error &&
          (client_.error() & 0xFF00) != kErrParamRecord) {
        finish_error(client_.error());  // a negative response: the drive refused the reset
      } else if (client_.state() != ParamClient::State::Writing &&
                 client_.state() != ParamClient::State::Idle) {
        // Written: the response may be lost with the reset (record refused).
        client_.reset();
        go(kWaitBack);
      } else if (timed_out) {
        finish_error(kErrAbsResetTimeout);
      }
      break;
    case kWaitBack:
      if (!axis.Port.online()) seen_offline_ = true;
      // Back: online again, restarted (not enabled, no fault).
      if (seen_offline_ && axis.Port.online() && !axis.drive_fault() && !axis.operation_enabled()) {
        axis.reset_errors();  // the outage was the reset we asked for
        axis.InhibitPower = false;
        Busy = false;
        Done = true;
        Step = kDone;
      } else if (timed_out) {
        finish_error(kErrAbsResetTimeout);
      }
      break;
    default:
      break;
  }
  axis.block_done();
}

}  // namespace plc::drive
