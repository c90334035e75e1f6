#include "bench/harness/commands/info_commands.hpp"

#include <cctype>
#include <cstdio>
#include <sstream>

#include "backends/backend.hpp"
#include "bench/harness/commands/commands.hpp"
#include "bench/harness/common/usage_error.hpp"
#include "bench/harness/run/run.hpp"
#include "scene_file/scene_file.hpp"
#include "scene_file/scene_file_text.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

const char* type_name(KnobSpec::Type type) {
  switch (type) {
    case KnobSpec::Type::number:
      return "number";
    case KnobSpec::Type::integer:
      return "integer";
    case KnobSpec::Type::boolean:
      return "boolean";
    case KnobSpec::Type::choice:
      return "choice";
  }
  return "";
}

// a knob's value in JSON as a scene file writes it: integers as integers, booleans as true/false,
// choices as the name
json knob_json(const KnobSpec& spec, double value) {
  if (spec.type == KnobSpec::Type::boolean) return value != 0.0;
  if (spec.type == KnobSpec::Type::choice) return choice_name(spec, value);
  if (spec.type == KnobSpec::Type::integer) return static_cast<long long>(value);
  return value;
}

json knob_entry(const KnobSpec& spec) {
  json entry = {{"name", spec.name},
                {"type", type_name(spec.type)},
                {"default", knob_json(spec, spec.default_value)},
                {"help", spec.help}};
  if (spec.type == KnobSpec::Type::choice) {
    entry["choices"] = spec.choices;
  } else if (spec.type != KnobSpec::Type::boolean) {
    entry["min"] = knob_json(spec, spec.min);
    entry["max"] = knob_json(spec, spec.max);
  }
  entry["unit"] = spec.unit;
  entry["doc"] = spec.doc.empty() ? spec.help : spec.doc;
  return entry;
}

// the build option that adds an optional backend of the project
std::string build_option(const std::string& name) {
  std::string option = "CHAINMAIL_WITH_";
  for (char c : name) option += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return option;
}

// six significant digits, for people (backends_json has the exact values)
std::string short_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

std::string knob_value_text(const KnobSpec& spec, double value) {
  if (spec.type == KnobSpec::Type::boolean) return value != 0.0 ? "true" : "false";
  if (spec.type == KnobSpec::Type::choice) return choice_name(spec, value);
  return short_number(value);
}

// "  name  type  default  [min, max]  help"
std::string knob_line(const KnobSpec& spec) {
  // appended piece by piece: GCC 12 misreads `"[" + text` as an overlapping copy
  std::string range;
  for (const std::string& name : spec.choices) range.append(range.empty() ? "" : "|").append(name);
  if (spec.type != KnobSpec::Type::boolean && spec.type != KnobSpec::Type::choice)
    range.append("[")
        .append(short_number(spec.min))
        .append(", ")
        .append(short_number(spec.max))
        .append("]");
  char line[256];
  std::snprintf(line, sizeof line, "  %-28s %-8s %-12s %-22s ", spec.name.c_str(),
                type_name(spec.type), knob_value_text(spec, spec.default_value).c_str(),
                range.c_str());
  std::string text = line;
  return text.append(spec.help).append("\n");
}

// rings of a weave without building it (a valid scene may be too large to lay out)
long long ring_count(const WeaveSpec& weave) {
  return weave.type == WeaveType::chain ? weave.cols : 1LL * weave.rows * weave.cols;
}

// "ok: scene 'curtain', 900 rings (4in1 30 x 30), 2 s; backends a, b; reference c"
std::string check_summary(const Scene& scene, const std::vector<std::string>& backends) {
  std::ostringstream text;
  text << "ok: scene '" << scene.name << "', " << ring_count(scene.weave) << " rings ("
       << to_string(scene.weave.type);
  if (scene.weave.type != WeaveType::chain)
    text << " " << scene.weave.rows << " x " << scene.weave.cols;
  text << "), " << show_number(scene.duration) << " s; backends " << join_names(backends)
       << "; reference " << scene.reference;
  if (!backend_built(scene.reference)) text << " (not built into this binary: no drape_rms)";
  return text.str();
}

}  // namespace

json backends_json() {
  json list = json::array();
  for (const std::string& name : known_backend_names()) {
    json entry = {{"name", name}, {"built", backend_built(name)}};
    if (const BackendInfo* info = find_backend(name)) {
      entry["summary"] = info->summary;
      entry["cloth_surface"] = info->cloth_surface;
      entry["knobs"] = json::array();
      for (const KnobSpec& spec : info->knobs) entry["knobs"].push_back(knob_entry(spec));
    } else {
      entry["build_option"] = build_option(name);
    }
    list.push_back(entry);
  }
  return {{"backends", list}};
}

std::string backends_text() {
  std::string text;
  for (const std::string& name : known_backend_names()) {
    const BackendInfo* info = find_backend(name);
    if (!info) {
      text += name + ": not built into this binary (configure with -D" + build_option(name) +
              "=ON); docs/backends.md lists its knobs\n\n";
      continue;
    }
    text += name + ": " + info->summary + "\n";
    char header[256];
    std::snprintf(header, sizeof header, "  %-28s %-8s %-12s %-22s %s\n", "knob", "type", "default",
                  "range", "meaning");
    text += header;
    for (const KnobSpec& spec : info->knobs) text += knob_line(spec);
    text += "\n";
  }
  return text +
         "Set a knob in a scene under backends.<name>.<knob>, or with --set "
         "backends.<name>.<knob>=VALUE.\n";
}

int backends_command(bool as_json) {
  const std::string text = as_json ? backends_json().dump(2) + "\n" : backends_text();
  std::fputs(text.c_str(), stdout);
  return kExitOk;
}

int check_command(const CheckCommand& command, std::FILE* out) {
  int status = kExitOk;
  for (const std::string& file : command.scene_files) {
    try {
      const Scene scene = load_scene_file(file, command.overrides);
      validate_backend_knobs(scene);
      const std::vector<std::string> backends = select_backends(scene, {});
      const std::string line = command.resolved ? scene_to_json(scene).dump()
                                                : file + ": " + check_summary(scene, backends);
      std::fprintf(out, "%s\n", line.c_str());
    } catch (const SceneError& e) {
      std::fprintf(stderr, "chainmail: %s\n", e.what());
      status = kExitBadInput;
    } catch (const UsageError& e) {
      std::fprintf(stderr, "chainmail: %s\n", e.what());
      status = kExitBadInput;
    }
  }
  return status;
}

}  // namespace chainmail
