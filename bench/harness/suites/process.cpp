#include "bench/harness/suites/process.hpp"

#include <fcntl.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench/harness/common/data_dir.hpp"
#include "bench/harness/common/interrupt.hpp"

extern char** environ;

namespace chainmail {

std::string shell_quote(const std::string& s) {
  // plain words stay as they are, so that printed command lines read naturally
  if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                        "0123456789-_./,:+") == std::string::npos) {
    return s;
  }
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

void run_parallel(int count, int jobs, const std::function<void(int)>& job) {
  std::atomic<int> next{0};
  std::vector<std::thread> workers;
  for (int w = 0; w < std::max(1, jobs); ++w) {
    workers.emplace_back([&] {
      for (int k = next++; k < count; k = next++) job(k);
    });
  }
  for (auto& t : workers) t.join();
}

int run_child(const std::vector<std::string>& argv, const std::string& log) {
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&files, 1, 2);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int failed = posix_spawn(&pid, args[0], &files, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  if (failed) return -1;
  bool passed_on = false;
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (interrupted() && !passed_on) ::kill(pid, SIGTERM), passed_on = true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::string plotting_python() {
  for (const char* candidate : {"/usr/bin/python3", "python3"}) {
    const std::string probe = std::string(candidate) + " -c 'import matplotlib' >/dev/null 2>&1";
    if (std::system(probe.c_str()) == 0) return candidate;
  }
  return "";
}

bool make_plot(const std::string& script, const std::vector<std::string>& args) {
  const std::string python = plotting_python();
  if (python.empty()) {
    std::fprintf(stderr, "chainmail: no python3 with matplotlib: plot skipped\n");
    return false;
  }
  // one word at a time (appending, not `" " + word`, which GCC 12 misreads as an overlap)
  std::string command = python;
  command.append(" ").append(shell_quote(data_dir().plot_script(script)));
  for (const auto& a : args) command.append(" ").append(shell_quote(a));
  return std::system(command.c_str()) == 0;
}

}  // namespace chainmail
