#pragma once
// CPU clocks for the figures a loaded machine cannot inflate: a study times each run by the CPU of the thread
// that runs it (oneTBB limited to one thread, so the kernels run there, while other runs go on beside it);
// `clothsim run --stats` times its load phases by the CPU of the whole process (all threads).

namespace clothsim::sim {

double thread_cpu_seconds();   // CLOCK_THREAD_CPUTIME_ID
double process_cpu_seconds();  // CLOCK_PROCESS_CPUTIME_ID

}  // namespace clothsim::sim
