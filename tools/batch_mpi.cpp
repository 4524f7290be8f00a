#include "tools/batch_mpi.h"

#ifdef CLOTHSIM_HAVE_MPI
#include <mpi.h>

#include <cstdlib>
#include <sstream>
#include <string>

#include "tools/scene_process.h"
#endif

namespace clothsim::cli {

#ifndef CLOTHSIM_HAVE_MPI

bool batch_mpi_start(int&) { return false; }
void batch_mpi_finalize() {}
void batch_mpi_run(std::vector<BatchScene>&, const std::vector<std::size_t>&, int, int,
                   const std::function<void(const BatchScene&)>&) {}

#else

namespace {

constexpr int tag_work = 1;    // rank 0 -> worker: a scene index, or -1 for "no more"
constexpr int tag_result = 2;  // worker -> rank 0: the result of the last scene (index -1: ready for a first)

// A result travels as text: "index exit_code frames wall_seconds\nstatus\nmessage".
std::string encode_result(long index, const BatchScene& s) {
  std::ostringstream o;
  o.precision(17);
  o << index << ' ' << s.exit_code << ' ' << s.frames << ' ' << s.wall_seconds << '\n' << s.status << '\n' << s.message;
  return o.str();
}

long decode_result(const std::string& text, std::vector<BatchScene>& scenes) {
  std::istringstream in(text);
  long index = -1;
  BatchScene r;
  in >> index >> r.exit_code >> r.frames >> r.wall_seconds;
  in.ignore(1);
  std::getline(in, r.status);
  std::getline(in, r.message, '\0');
  if (index < 0 || std::size_t(index) >= scenes.size()) return -1;
  BatchScene& s = scenes[std::size_t(index)];
  s.exit_code = r.exit_code;
  s.frames = r.frames;
  s.wall_seconds = r.wall_seconds;
  s.status = r.status;
  s.message = r.message;
  return index;
}

void dispatch(std::vector<BatchScene>& scenes, const std::vector<std::size_t>& queue,
              const std::function<void(const BatchScene&)>& on_done) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  std::size_t next = 0;
  int stopped = 0;
  while (stopped < size - 1) {
    MPI_Status st;
    MPI_Probe(MPI_ANY_SOURCE, tag_result, MPI_COMM_WORLD, &st);
    int bytes = 0;
    MPI_Get_count(&st, MPI_CHAR, &bytes);
    std::string text(std::size_t(bytes), '\0');
    MPI_Recv(text.data(), bytes, MPI_CHAR, st.MPI_SOURCE, tag_result, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    const long done = decode_result(text, scenes);
    if (done >= 0) on_done(scenes[std::size_t(done)]);
    long work = -1;
    if (next < queue.size()) work = long(queue[next++]);
    else ++stopped;
    MPI_Send(&work, 1, MPI_LONG, st.MPI_SOURCE, tag_work, MPI_COMM_WORLD);
  }
}

void work(std::vector<BatchScene>& scenes, int threads, int checkpoint_every) {
  std::string result = encode_result(-1, BatchScene{});
  while (true) {
    MPI_Send(result.data(), int(result.size()), MPI_CHAR, 0, tag_result, MPI_COMM_WORLD);
    long index = -1;
    MPI_Recv(&index, 1, MPI_LONG, 0, tag_work, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (index < 0) return;
    BatchScene s = scenes[std::size_t(index)];
    try {
      SceneProcess p(s, threads, checkpoint_every);
      p.finish(s);
    } catch (const std::exception& e) {  // this scene could not start; report it and take the next
      s.status = "failed";
      s.exit_code = 2;
      s.message = e.what();
    }
    result = encode_result(index, s);
  }
}

}  // namespace

bool batch_mpi_start(int& rank) {
  // Only under a launcher: a plain `clothsim batch` must not initialise MPI (slow, and it may need a daemon).
  const bool launched = std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE") || std::getenv("PMIX_RANK");
  if (!launched) return false;
  MPI_Init(nullptr, nullptr);
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (size > 1) return true;
  MPI_Finalize();
  return false;
}

void batch_mpi_finalize() { MPI_Finalize(); }

void batch_mpi_run(std::vector<BatchScene>& scenes, const std::vector<std::size_t>& queue, int threads,
                   int checkpoint_every, const std::function<void(const BatchScene&)>& on_done) {
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) dispatch(scenes, queue, on_done);
  else work(scenes, threads, checkpoint_every);
}

#endif

}  // namespace clothsim::cli
