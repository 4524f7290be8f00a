#pragma once
// What one step tells the frame loop besides the state it wrote.

namespace clothsim {

// failed: the step's state is not to be trusted although it may be finite (a linear solve stopped at its
// iteration cap short of its tolerance). Any integrator or stage can set it; sim/frame_stepper.h rejects the
// step and retries it smaller.
struct StepResult {
  bool failed = false;
};

}  // namespace clothsim
