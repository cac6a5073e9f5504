#include "ppp_bayes_tree/io/epoch_time_screen.h"

#include <cstdio>

namespace ppp {

EpochTimeGuardOptions streamEpochTimeOptions() {
  EpochTimeGuardOptions o;
  o.max_forward_step_s = 600.0;
  o.out_of_order_window_s = 60.0;
  o.confirm_epochs = 3;
  o.drop_out_of_order = true;
  return o;
}

StreamProblem epochTimeProblem(TimeDropReason reason, const GnssTime& time, double step_s, const EpochOrigin& origin) {
  StreamProblem p;
  p.kind = StreamProblemKind::EpochTimeRefused;
  p.byte_offset = origin.byte_offset;
  p.frame_index = origin.frame_index;
  p.message_type = origin.message_type;
  char step[64];
  std::snprintf(step, sizeof step, "%.3f s %s", step_s < 0.0 ? -step_s : step_s, step_s < 0.0 ? "before" : "after");
  p.detail = "epoch " + time.toString() + " is " + step + " the accepted epoch " + (time - step_s).toString() + ": " +
             text(reason) + ": dropped";
  return p;
}

}  // namespace ppp
