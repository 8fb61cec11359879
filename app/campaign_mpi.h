// predvs app — the runs of a campaign over MPI ranks (`mpirun -np K predvs compare ...`, issue #12).
//
// Launched by mpirun (Open MPI: OMPI_COMM_WORLD_SIZE in the environment; also PMI_SIZE), predvs
// initialises MPI (MPI_THREAD_SERIALIZED) at the first mpiWorld() and finalises it at exit. Built
// without MPI (PREDVS_WITH_MPI undefined: CMake did not find it), a launch with several ranks is
// an error instead of K copies of the same campaign.
//
// Dynamic hand-out (runs differ in cost by orders of magnitude): every rank runs `threads` worker
// threads (slots); a slot asks rank 0 for a run index, and holds one more in reserve: when a run
// ends it starts the reserved one at once and sends the record of the finished run (a
// non-blocking send) with a request for the next index, so the round trip overlaps a run. -1
// means none left. Rank 0's own threads take runs from the same list; rank 0's main thread only
// answers (MPI_Iprobe, then a 1 ms sleep when idle, hidden by the reserve) and passes every
// finished record to `done` (on one thread at a time). At the end each rank reports its
// hand-out wait and run times, printed on stderr by rank 0 (never in the outputs).
// The first failure (a run's exception here or on another rank, or `done` throwing, e.g.
// --stop-after) stops the hand-out: every rank finishes the runs it holds, then rank 0 rethrows.
// Every rank builds the same plan from the same files (a shared file system, or the same copies).
#pragma once

#include <cstddef>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace predvs {

struct MpiWorld {
  int rank = 0;
  int size = 1;  ///< 1: not under mpirun (or one rank)
};

/// The calling process's rank and the number of ranks (MPI initialised on first call when launched
/// by mpirun). Throws std::runtime_error when launched with several ranks and built without MPI.
MpiWorld mpiWorld();

/// Whether this build has MPI.
bool mpiBuilt();

/// Runs the jobs `to_compute` (rank 0's list; ignored elsewhere) over every rank, `threads` worker
/// threads per rank. compute(j) runs job j and returns its record text; done(j, text) stores it
/// (rank 0 only). Returns on every rank when all ranks are finished; rethrows the first failure on
/// rank 0.
void mpiRunJobs(const MpiWorld& world, const std::vector<size_t>& to_compute, int threads,
                const std::function<std::string(size_t)>& compute,
                const std::function<void(size_t, const std::string&)>& done, std::ostream& err);

}  // namespace predvs
