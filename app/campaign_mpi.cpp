#include "campaign_mpi.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
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

// worker -> 0: "<slot> N" (asks for an index), "<slot> R<job>\n<record>" (a result, and asks for
// an index), "<slot> F<job>\n<record>" (the slot's last result), "<slot> E<message>" (a failure)
constexpr int kTagReady = 1;
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

using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

void workerRank(int threads, const std::function<std::string(size_t)>& compute) {
  std::mutex mpi_mutex;  // MPI_THREAD_SERIALIZED: one MPI call at a time
  double times[3] = {0.0, 0.0, 0.0};  // hand-out wait (s), compute (s), runs: reported to rank 0 at the end
  std::vector<std::thread> pool;
  for (int s = 0; s < threads; ++s)
    pool.emplace_back([&, s] {
      const std::string slot = std::to_string(s) + " ";
      auto send = [&](const std::string& msg) {
        MPI_Send(msg.data(), static_cast<int>(msg.size()), MPI_CHAR, 0, kTagReady, MPI_COMM_WORLD);
      };
      // One run in reserve: the next index is asked for before the current run starts, so the
      // round trip to rank 0 overlaps the run instead of following it.
      long long cur = -1, next = -1;
      MPI_Request request = MPI_REQUEST_NULL, sending = MPI_REQUEST_NULL;
      std::string in_flight;
      {
        std::lock_guard<std::mutex> lock(mpi_mutex);
        send(slot + "N");
        MPI_Recv(&cur, 1, MPI_LONG_LONG, 0, kTagJob + s, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        if (cur >= 0) {
          send(slot + "N");
          MPI_Irecv(&next, 1, MPI_LONG_LONG, 0, kTagJob + s, MPI_COMM_WORLD, &request);
        }
      }
      while (cur >= 0) {
        std::string msg;
        try {
          const auto t1 = Clock::now();
          const std::string text = compute(static_cast<size_t>(cur));
          std::lock_guard<std::mutex> lock(mpi_mutex);
          times[1] += seconds(t1, Clock::now());
          times[2] += 1.0;
          msg = "R" + std::to_string(cur) + "\n" + text;
        } catch (const std::exception& e) {
          msg = std::string("E") + e.what();
        } catch (...) {
          msg = "Eunknown error";
        }
        const auto t0 = Clock::now();
        auto wait = [&](MPI_Request& r) {  // polls, so that the other slots may use MPI meanwhile
          for (int done = 0;;) {
            {
              std::lock_guard<std::mutex> lock(mpi_mutex);
              MPI_Test(&r, &done, MPI_STATUS_IGNORE);
            }
            if (done) return;
            std::this_thread::sleep_for(std::chrono::microseconds(50));
          }
        };
        wait(request);  // the reserved index (normally here long ago)
        wait(sending);  // the previous result (normally received long ago)
        std::lock_guard<std::mutex> lock(mpi_mutex);
        if (msg[0] == 'E' || next < 0) {  // 'F': the last result of this slot, no reply wanted
          send(slot + (msg[0] == 'E' ? msg : "F" + msg.substr(1)));
          times[0] += seconds(t0, Clock::now());
          return;
        }
        in_flight = slot + msg;  // the result, and a request for one more index; sent while the next run runs
        MPI_Isend(in_flight.data(), static_cast<int>(in_flight.size()), MPI_CHAR, 0, kTagReady, MPI_COMM_WORLD,
                  &sending);
        cur = next;
        MPI_Irecv(&next, 1, MPI_LONG_LONG, 0, kTagJob + s, MPI_COMM_WORLD, &request);
        times[0] += seconds(t0, Clock::now());
      }
    });
  for (auto& t : pool) t.join();
  MPI_Send(times, static_cast<int>(sizeof times), MPI_CHAR, 0, kTagDone, MPI_COMM_WORLD);
}

}  // namespace

bool mpiBuilt() { return true; }

MpiWorld mpiWorld() { return session().world; }

void mpiRunJobs(const MpiWorld& world, const std::vector<size_t>& to_compute, int threads,
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
    if (stopping || next >= to_compute.size()) return -1;
    return static_cast<long long>(to_compute[next++]);
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
  double worker_times[3] = {0.0, 0.0, 0.0};
  std::string buffer;
  while (ranks_done < world.size - 1) {
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
    if (!flag) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));  // the reserve hides this latency
      continue;
    }
    int count = 0;
    MPI_Get_count(&status, MPI_CHAR, &count);
    buffer.resize(static_cast<size_t>(count));
    MPI_Recv(&buffer[0], count, MPI_CHAR, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (status.MPI_TAG == kTagDone) {
      ++ranks_done;
      double t[3];
      if (buffer.size() == sizeof t) {
        std::memcpy(t, buffer.data(), sizeof t);
        for (int k = 0; k < 3; ++k) worker_times[k] += t[k];
      }
      continue;
    }
    const size_t space = buffer.find(' ');
    const int slot = std::atoi(buffer.substr(0, space).c_str());
    const char kind = buffer.at(space + 1);
    long long j;
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (kind == 'R' || kind == 'F') {
        const size_t nl = buffer.find('\n', space);
        finish(static_cast<size_t>(std::atoll(buffer.substr(space + 2, nl - space - 2).c_str())), buffer.substr(nl + 1));
      } else if (kind == 'E') {
        fail(std::make_exception_ptr(
            std::runtime_error("rank " + std::to_string(status.MPI_SOURCE) + ": " + buffer.substr(space + 2))));
      }
      if (kind == 'F' || kind == 'E') continue;  // no reply wanted
      j = take();
    }
    MPI_Send(&j, 1, MPI_LONG_LONG, status.MPI_SOURCE, kTagJob + slot, MPI_COMM_WORLD);
  }
  for (auto& t : pool) t.join();
  if (worker_times[2] > 0)  // stderr only: the outputs never hold times
    err << "predvs: compare: MPI hand-out on ranks 1.." << world.size - 1 << ": " << static_cast<long>(worker_times[2])
        << " runs, mean run " << 1e3 * worker_times[1] / worker_times[2] << " ms, mean wait for the next run "
        << 1e3 * worker_times[0] / worker_times[2] << " ms ("
        << 100.0 * worker_times[0] / std::max(1e-12, worker_times[1]) << " % of a run)\n";
  if (error) std::rethrow_exception(error);
}

#endif

}  // namespace predvs
