// What the suites run outside this process: `chainmail run` children for sweep points, jobs in
// parallel, the plot script from the data folder (data_dir.hpp).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace chainmail {

// a word for a shell command line: plain words as they are, anything else in single quotes
std::string shell_quote(const std::string& word);

// runs `count` jobs on `jobs` threads; job(k) is called once for each k
void run_parallel(int count, int jobs, const std::function<void(int)>& job);

// runs `argv` to completion with stdout and stderr into `log`; a signal to this process is passed
// on as SIGTERM (so the child writes what it finished). Returns the exit status (-1: no start).
int run_child(const std::vector<std::string>& argv, const std::string& log);

// a python interpreter with matplotlib for the plots ("" when none)
std::string plotting_python();

// runs the data folder's <script> with `args` through plotting_python(); false (with a note) when
// it cannot
bool make_plot(const std::string& script, const std::vector<std::string>& args);

}  // namespace chainmail
