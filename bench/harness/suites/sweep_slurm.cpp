// `chainmail sweep --slurm FILE`: a script that submits a sweep to Slurm as three jobs: the
// reference run into the cache, the points as a job array that starts once it is there (one
// point per task), and --gather once every point has ended.
#include <sys/stat.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/output/output.hpp"
#include "bench/harness/suites/process.hpp"
#include "bench/harness/suites/sweep_jobs.hpp"

namespace chainmail {
namespace fs = std::filesystem;

namespace {

// the script's second line: a file that starts otherwise is not chainmail's, and is not replaced
constexpr const char* kSlurmMarker = "# chainmail sweep --slurm: Slurm jobs for one sweep";

// a script already at `path` may be replaced only when chainmail wrote it
void check_script_path(const std::string& path) {
  struct stat info {};
  if (::lstat(path.c_str(), &info) != 0) return;
  if (!S_ISREG(info.st_mode))
    throw UsageError("--slurm '" + path + "': exists and is not a file chainmail wrote");
  std::ifstream in(path);
  std::string first, second;
  std::getline(in, first);
  std::getline(in, second);
  if (second != kSlurmMarker)
    throw UsageError("--slurm '" + path + "': exists and chainmail did not write it: refusing to " +
                     "replace it");
}

std::string absolute(const std::string& path) {
  return fs::absolute(path).lexically_normal().string();
}

// every point's command line, one `case` branch per array task
std::string array_body(const SweepPlan& plan, const SweepJobs& jobs, const std::string& out) {
  std::ostringstream body;
  body << "#!/bin/bash\nset -euo pipefail\ncase \"$SLURM_ARRAY_TASK_ID\" in\n";
  for (size_t k = 0; k < plan.points.size(); ++k)
    body << "  " << k << ") exec " << command_line(jobs.args(plan.points[k], k, out)) << " ;;\n";
  body << "  *) echo \"no point $SLURM_ARRAY_TASK_ID\" >&2; exit 2 ;;\nesac\n";
  return body.str();
}

}  // namespace

void write_slurm_script(const SweepCommand& command, const SweepPlan& plan) {
  const std::string path = command.slurm;
  check_script_path(path);
  if (plan.jobs.cache.empty())
    throw UsageError(
        "--slurm: the points read the reference from the cache: give --cache DIR "
        "(a shared folder), not none");
  // every path absolute: the jobs run on other nodes, from other folders
  SweepJobs jobs = plan.jobs;
  jobs.scene_file = absolute(jobs.scene_file);
  jobs.cache = absolute(jobs.cache);
  const std::string out = absolute(plan.out);
  const std::string logs = absolute(path) + ".logs";
  // each point is one single-threaded run (every backend steps on one thread)
  const std::string flags = "--ntasks=1 --cpus-per-task=1";
  const std::string reference = command_line(sweep_args(command, jobs, {"--reference-only"}));
  const std::string gather = command_line(sweep_args(command, jobs, {"--gather", out}));

  std::ostringstream s;
  s << "#!/bin/bash\n"
    << kSlurmMarker << "\n"
    << "# " << plan.points.size() << " points of " << jobs.scene_file << " into " << out << ".\n"
    << "# `bash " << shell_quote(absolute(path)) << "` submits the reference run (into the "
    << "cache), the points as a\n# job array that starts once it ended well, and the gather "
    << "(sweep.csv, sweep.png) once every point\n# ended. The folders above, the cache and the "
    << "chainmail binary must be on a file system that\n# every node sees. Logs: " << logs
    << "/. Rewrite it with the same sweep and --slurm.\n"
    << "set -euo pipefail\n"
    << "logs=" << shell_quote(logs) << "\n"
    << "mkdir -p \"$logs\"\n"
    << "job_id() { echo \"${1%%;*}\"; }  # sbatch --parsable: JOBID[;CLUSTER]\n"
    << "reference=$(job_id \"$(sbatch --parsable --job-name=chainmail-reference " << flags
    << " --output=\"$logs/reference.log\" --wrap=" << shell_quote(reference) << ")\")\n"
    << "points=$(job_id \"$(sbatch --parsable --job-name=chainmail-points " << flags
    << " --array=0-" << plan.points.size() - 1
    << " --kill-on-invalid-dep=yes --dependency=afterok:\"$reference\" "
       "--output=\"$logs/point-%a.log\" <<'POINTS'\n"
    << array_body(plan, jobs, out) << "POINTS\n)\")\n"
    << "gather=$(job_id \"$(sbatch --parsable --job-name=chainmail-gather " << flags
    << " --kill-on-invalid-dep=yes --dependency=afterany:\"$points\" --output=\"$logs/gather.log\" "
       "--wrap="
    << shell_quote(gather) << ")\")\n"
    << "echo \"reference $reference, points $points (" << plan.points.size()
    << " tasks), gather $gather\"\n";
  write_file_atomic(path, s.str());
  fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                  fs::perm_options::add);
  std::fprintf(stderr, "wrote %s (%zu points): submit it with bash %s\n", path.c_str(),
               plan.points.size(), path.c_str());
}

}  // namespace chainmail
