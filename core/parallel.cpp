// threads_for_step: the cores other processes leave free, measured from the machine's and this
// process's CPU time over windows of a tenth of a second.
#include "core/parallel.hpp"

#include <time.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

namespace chainmail {
namespace {

// CPU seconds every core of the machine has spent busy since boot (/proc/stat's first line);
// negative when unknown (not Linux, no /proc)
double machine_busy_seconds() {
  std::FILE* file = std::fopen("/proc/stat", "r");
  if (!file) return -1.0;
  unsigned long long user = 0, nice = 0, system = 0, idle = 0, iowait = 0, irq = 0, softirq = 0,
                     steal = 0;
  const int got = std::fscanf(file, "cpu %llu %llu %llu %llu %llu %llu %llu %llu", &user, &nice,
                              &system, &idle, &iowait, &irq, &softirq, &steal);
  std::fclose(file);
  if (got < 4) return -1.0;
  static const double tick = [] {
    const long hz = sysconf(_SC_CLK_TCK);
    return hz > 0 ? 1.0 / static_cast<double>(hz) : 0.01;
  }();
  // niced processes count too: a thread woken at a barrier waits for the core they hold for up to
  // the scheduler's wake-up granularity, dozens of times a step
  return static_cast<double>(user + nice + system + irq + softirq + steal) * tick;
}

// threads of other processes running or waiting for a core right now (/proc/loadavg's fourth
// field counts them with this one); 0 when unknown
int other_runnable_threads() {
  std::FILE* file = std::fopen("/proc/loadavg", "r");
  if (!file) return 0;
  double load[3];
  int runnable = 0, threads = 0;
  const int got =
      std::fscanf(file, "%lf %lf %lf %d/%d", &load[0], &load[1], &load[2], &runnable, &threads);
  std::fclose(file);
  return got == 5 ? std::max(0, runnable - 1) : 0;
}

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// the last window's measurement, shared by every model of the process
struct CoreMonitor {
  static constexpr double kWindow = 0.1;  // s; /proc/stat counts in ticks of 10 ms
  std::mutex lock;
  bool enabled = true, started = false;
  double wall = 0.0, machine = 0.0, self = 0.0;  // at the window's start
  double free_cores = 1e9;                       // the last window's; all until measured

  CoreMonitor() {
    const char* adapt = std::getenv("CHAINMAIL_ADAPT_THREADS");
    enabled = !(adapt && std::strcmp(adapt, "0") == 0) && machine_busy_seconds() >= 0.0;
  }

  void update() {
    const double now = wall_seconds();
    if (started && now - wall < kWindow) return;
    const double busy = machine_busy_seconds(), mine = process_cpu_seconds();
    if (started) {
      // cores the others kept busy: every busy core-second that was not this process's
      const double others = std::max(0.0, (busy - machine) - (mine - self)) / (now - wall);
      free_cores = hardware_threads() - others;
    } else {
      // before the first window, the threads runnable now: on a busy machine a first step on
      // every thread can take a hundred of its steps on one
      free_cores = hardware_threads() - other_runnable_threads();
    }
    started = true;
    wall = now, machine = busy, self = mine;
  }
};

CoreMonitor& monitor() {
  static CoreMonitor instance;
  return instance;
}

}  // namespace

int threads_for_step(int requested) {
  if (requested <= 1) return 1;
  CoreMonitor& m = monitor();
  if (!m.enabled) return requested;
  double free_cores;
  {
    // one thread measures at a time; the others take the last window's figure
    std::unique_lock<std::mutex> hold(m.lock, std::try_to_lock);
    if (hold.owns_lock()) m.update();
    free_cores = m.free_cores;
  }
  // a thread beyond the free cores waits for one at every barrier, and the team waits for it:
  // half a free core is not worth a thread
  const int usable = static_cast<int>(std::floor(free_cores + 0.5));
  return std::clamp(usable, 1, requested);
}

}  // namespace chainmail
