#include "campaign_mpi.h"

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#ifdef PREDVS_WITH_MPI
#include <mpi.h>
#endif

namespace predvs {
namespace {

/// Ranks announced by the launcher (0 when not launched by mpirun).
int launcherSize() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"})
    if (const char* v = std::getenv(var)) return std::atoi(v);
  return 0;
}

}  // namespace

#ifndef PREDVS_WITH_MPI

bool mpiBuilt() { return false; }

MpiWorld mpiWorld() {
  if (launcherSize() > 1)
    throw std::runtime_error("launched by mpirun with " + std::to_string(launcherSize()) +
                             " ranks, but this predvs was built without MPI (install libopenmpi-dev and rebuild)");
  return {};
}

void mpiRunJobs(const MpiWorld&, const std::vector<size_t>&, int, const std::function<std::string(size_t)>&,
                const std::function<void(size_t, const std::string&)>&, std::ostream&) {
  throw std::logic_error("mpiRunJobs: built without MPI");
}

#else

namespace {

constexpr int kTagReady = 1;   // worker -> 0: "<slot> N" | "<slot> R<job>\n<record>" | "<slot> E<message>"
constexpr int kTagDone = 2;    // worker -> 0: every slot closed
constexpr int kTagJob = 100;   // 0 -> worker slot s: tag kTagJob + s, one long long (-1: none left)

struct MpiSession {
  MpiWorld world;
  bool initialised = false;
  MpiSession() {
    if (launcherSize() < 1) return;
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
    if (provided < MPI_THREAD_SERIALIZED) {
      MPI_Abort(MPI_COMM_WORLD, 2);
    }
    initialised = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &world.rank);
    MPI_Comm_size(MPI_COMM_WORLD, &world.size);
  }
  ~MpiSession() {
    int finalized = 0;
    if (initialised && (MPI_Finalized(&finalized), !finalized)) MPI_Finalize();
  }
};

MpiSession& session() {
  static MpiSession s;
  return s;
}

void workerRank(int threads, const std::function<std::string(size_t)>& compute) {
  std::mutex mpi_mutex;  // MPI_THREAD_SERIALIZED: one MPI call at a time
  std::vector<std::thread> pool;
  for (int s = 0; s < threads; ++s)
    pool.emplace_back([&, s] {
      std::string msg = std::to_string(s) + " N";
      for (;;) {
        long long j = -1;
        {
          std::lock_guard<std::mutex> lock(mpi_mutex);
          MPI_Send(msg.data(), static_cast<int>(msg.size()), MPI_CHAR, 0, kTagReady, MPI_COMM_WORLD);
          MPI_Recv(&j, 1, MPI_LONG_LONG, 0, kTagJob + s, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        }
        if (j < 0) return;
        try {
          msg = std::to_string(s) + " R" + std::to_string(j) + "\n" + compute(static_cast<size_t>(j));
        } catch (const std::exception& e) {
          msg = std::to_string(s) + " E" + e.what();
        } catch (...) {
          msg = std::to_string(s) + " Eunknown error";
        }
      }
    });
  for (auto& t : pool) t.join();
  char none = 0;
  MPI_Send(&none, 0, MPI_CHAR, 0, kTagDone, MPI_COMM_WORLD);
}

}  // namespace

bool mpiBuilt() { return true; }

MpiWorld mpiWorld() { return session().world; }

void mpiRunJobs(const MpiWorld& world, const std::vector<size_t>& todo, int threads,
                const std::function<std::string(size_t)>& compute,
                const std::function<void(size_t, const std::string&)>& done, std::ostream& err) {
  threads = std::max(1, threads);
  if (world.rank != 0) {
    workerRank(threads, compute);
    return;
  }
  std::mutex mutex;  // guards next, error, done()
  size_t next = 0;
  std::exception_ptr error;
  bool stopping = false;
  auto take = [&]() -> long long {  // with `mutex` held
    if (stopping || next >= todo.size()) return -1;
    return static_cast<long long>(todo[next++]);
  };
  auto fail = [&](std::exception_ptr e) {  // with `mutex` held
    if (!error) error = e;
    stopping = true;
  };
  auto finish = [&](size_t j, const std::string& text) {  // with `mutex` held
    try {
      done(j, text);
    } catch (...) {
      fail(std::current_exception());
    }
  };
  std::vector<std::thread> pool;
  for (int s = 0; s < threads; ++s)
    pool.emplace_back([&] {
      for (;;) {
        long long j;
        {
          std::lock_guard<std::mutex> lock(mutex);
          j = take();
        }
        if (j < 0) return;
        try {
          const std::string text = compute(static_cast<size_t>(j));
          std::lock_guard<std::mutex> lock(mutex);
          finish(static_cast<size_t>(j), text);
        } catch (...) {
          std::lock_guard<std::mutex> lock(mutex);
          fail(std::current_exception());
        }
      }
    });
  int ranks_done = 0;
  std::string buffer;
  while (ranks_done < world.size - 1) {
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
    if (!flag) {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      continue;
    }
    int count = 0;
    MPI_Get_count(&status, MPI_CHAR, &count);
    buffer.resize(static_cast<size_t>(count));
    MPI_Recv(&buffer[0], count, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (status.MPI_TAG == kTagDone) {
      ++ranks_done;
      continue;
    }
    const size_t space = buffer.find(' ');
    const int slot = std::atoi(buffer.substr(0, space).c_str());
    const char kind = buffer.at(space + 1);
    long long j;
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (kind == 'R') {
        const size_t nl = buffer.find('\n', space);
        finish(static_cast<size_t>(std::atoll(buffer.substr(space + 2, nl - space - 2).c_str())), buffer.substr(nl + 1));
      } else if (kind == 'E') {
        fail(std::make_exception_ptr(
            std::runtime_error("rank " + std::to_string(status.MPI_SOURCE) + ": " + buffer.substr(space + 2))));
      }
      j = take();
    }
    MPI_Send(&j, 1, MPI_LONG_LONG, status.MPI_SOURCE, kTagJob + slot, MPI_COMM_WORLD);
  }
  for (auto& t : pool) t.join();
  (void)err;
  if (error) std::rethrow_exception(error);
}

#endif

}  // namespace predvs
