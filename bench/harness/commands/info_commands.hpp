// The subcommands that run nothing: `chainmail backends` (every backend and its knobs) and
// `chainmail check` (validate scene files). Callable from tests without a process.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace chainmail {

// every backend the project has (built into this binary or not) and every registered one, in
// registry order: name, whether built, summary, and each knob's type, default, range and help
nlohmann::json backends_json();
// the same as text for people: one block per backend, one line per knob
std::string backends_text();
// `chainmail backends [--json]`: prints one of them on stdout; returns 0
int backends_command(bool as_json);

struct CheckCommand {
  std::vector<std::string> scene_files;
  std::vector<std::string> overrides;  // --set, applied to every file
  bool resolved = false;               // print each valid scene's resolved document
};
// validates every file as `chainmail run` would before running (scene keys, --set, backend
// knobs, at least one backend built into this binary) and runs nothing. Per valid file one line
// on stdout, "<file>: ok: ..." (or, with `resolved`, the resolved scene as one line of JSON); per
// invalid file the usual one-line message on stderr. Returns 0 when every file is valid, else 2.
int check_command(const CheckCommand& command, std::FILE* out = stdout);

}  // namespace chainmail
