#pragma once
// The `clothsim study` sub-commands, one file each (tools/study_<name>.cpp); each returns the exit code.
namespace clothsim::cli {

// study accuracy [--out DIR] [--quick]: work-precision and convergence of every integrator (docs/accuracy.md).
int study_accuracy(int argc, char** argv);
// study stability [--out DIR] [--quick]: largest stable step and stiffness against theory (docs/accuracy.md).
int study_stability(int argc, char** argv);
// study scaling SCENE.xml --threads 1,2,4 [--weak]: speed-up and parallel efficiency (docs/performance.md, "Scaling").
int study_scaling(int argc, char** argv);
// study autostep [SCENE.xml ...] [--family N]: the automatic step against the largest stable one (bisection).
int study_auto_step(int argc, char** argv);

}  // namespace clothsim::cli
