// The registry: which backends the project has and which this binary was built with, every
// backend's knob table (ranges, defaults, the binding to its settings, docs/backends.md), and the
// check of a scene's backend sections.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <numbers>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "backend_sim.hpp"

namespace chainmail {
namespace {

using json = nlohmann::json;

#if CHAINMAIL_HAVE_BULLET
constexpr bool kBulletBuilt = true;
#else
constexpr bool kBulletBuilt = false;
#endif
#if CHAINMAIL_HAVE_ODE
constexpr bool kOdeBuilt = true;
#else
constexpr bool kOdeBuilt = false;
#endif

Scene scene_with(const json& backends, const std::string& reference = "plausible") {
  return scene_from_json({{"name", "knobs"},
                          {"weave", {{"type", "chain"}, {"cols", 2}}},
                          {"duration", 1.0},
                          {"reference", reference},
                          {"backends", backends}},
                         "scene.json");
}

TEST(Registry, KnowsEveryBackendAndHasTheBuiltOnesInTheSameOrder) {
  const std::vector<std::string>& known = known_backend_names();
  // the project's own, then any registered by a test before this one
  ASSERT_GE(known.size(), 5u);
  EXPECT_EQ(std::vector<std::string>(known.begin(), known.begin() + 5),
            (std::vector<std::string>{"plausible", "massspring", "bullet", "ode", "torus_xpbd"}));
  auto next = known.begin();
  for (const BackendInfo& info : backend_registry()) {
    next = std::find(next, known.end(), info.name);
    ASSERT_NE(next, known.end()) << info.name << ": unknown or out of order";
    ++next;
    EXPECT_EQ(find_backend(info.name), &info);
    EXPECT_STREQ(info.create()->name(), info.name.c_str());
  }
  // the build options decide the optional ones; the others are always there
  EXPECT_TRUE(backend_built("plausible"));
  EXPECT_TRUE(backend_built("massspring"));
  EXPECT_TRUE(backend_built("torus_xpbd"));
  EXPECT_EQ(backend_built("bullet"), kBulletBuilt);
  EXPECT_EQ(backend_built("ode"), kOdeBuilt);
  for (const std::string& name : known) EXPECT_TRUE(backend_known(name)) << name;
  EXPECT_FALSE(backend_known("havok"));
  EXPECT_FALSE(backend_built("havok"));
  EXPECT_EQ(find_backend("havok"), nullptr);
}

TEST(Registry, RefusesAnUnknownBackendNamingEveryKnownOne) {
  try {
    validate_backend_knobs(scene_with({{"havok", json::object()}}));
    FAIL() << "no error";
  } catch (const SceneError& error) {
    EXPECT_STREQ(error.what(), ("scene.json: key 'backends.havok': unknown backend (known: " +
                                join_names(known_backend_names()) + ")")
                                   .c_str());
    EXPECT_TRUE(std::string(error.what()).find("plausible, massspring, bullet, ode, torus_xpbd") !=
                std::string::npos);
  }
  try {
    validate_backend_knobs(scene_with(json::object(), "havok"));
    FAIL() << "no error";
  } catch (const SceneError& error) {
    EXPECT_STREQ(error.what(), "scene.json: key 'reference': unknown backend 'havok'");
  }
}

TEST(Registry, SkipsTheSectionOfABackendThatIsNotBuiltWithANote) {
  for (const std::string& name : known_backend_names()) {
    SCOPED_TRACE(name);
    // a knob no backend has: refused by a built backend, unchecked for one that is not built
    const Scene scene = scene_with({{name, {{"no_such_knob", 1}}}}, name);
    if (backend_built(name)) {
      EXPECT_THROW(validate_backend_knobs(scene), SceneError);
      EXPECT_TRUE(validate_backend_knobs(scene_with({{name, json::object()}}, name)).empty());
    } else {
      const std::string note =
          "backends." + name + ": not built into this binary, its knobs are not checked";
      EXPECT_EQ(validate_backend_knobs(scene), std::vector<std::string>{note});
    }
  }
}

// ---------------------------------------------------------------------------------------------
// every backend's knob table

class KnobTableContract : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override { test::skip_unless_built(GetParam()); }
  const BackendInfo& info() const { return *find_backend(GetParam()); }
};

bool integral(double value) {
  return std::floor(value) == value;
}

TEST_P(KnobTableContract, DeclaresDtAndDefaultsWithinRange) {
  const KnobSpec* dt = find_knob(info(), "dt");
  ASSERT_NE(dt, nullptr);
  EXPECT_EQ(dt->type, KnobSpec::Type::number);
  EXPECT_GT(dt->min, 0.0);
  std::set<std::string> names;
  for (const KnobSpec& spec : info().knobs) {
    SCOPED_TRACE(spec.name);
    EXPECT_TRUE(names.insert(spec.name).second) << "declared twice";
    EXPECT_FALSE(spec.help.empty());
    EXPECT_LE(spec.min, spec.default_value);
    EXPECT_LE(spec.default_value, spec.max);
    if (spec.type == KnobSpec::Type::integer) {
      EXPECT_TRUE(integral(spec.min) && integral(spec.max) && integral(spec.default_value));
    }
    if (spec.type == KnobSpec::Type::boolean) {
      EXPECT_EQ(spec.min, 0.0);
      EXPECT_EQ(spec.max, 1.0);
      EXPECT_TRUE(spec.default_value == 0.0 || spec.default_value == 1.0);
    }
    if (spec.type == KnobSpec::Type::choice) {
      EXPECT_EQ(spec.min, 0.0);
      EXPECT_EQ(spec.max, double(spec.choices.size()) - 1.0);
      EXPECT_TRUE(integral(spec.default_value));
    } else {
      EXPECT_TRUE(spec.choices.empty());
    }
  }
}

// a value of the knob's range other than its default
double another_value(const KnobSpec& spec) {
  if (spec.type == KnobSpec::Type::boolean) return 1.0 - spec.default_value;
  const double value = spec.default_value < spec.max ? spec.max : spec.min;
  return spec.type == KnobSpec::Type::integer ? std::floor(value) : value;
}

TEST_P(KnobTableContract, BindsEveryKnobButDtToAFieldOfItsOwn) {
  ASSERT_TRUE(info().knob_round_trip);
  const Knobs defaults = resolve_knobs(scene_with(json::object()), info());
  Knobs bound = defaults;
  bound.erase("dt");  // it reaches a model only through step(dt)
  // the defaults are the default settings struct's fields: filled in and read back unchanged
  EXPECT_EQ(info().knob_round_trip(defaults), bound);
  // one knob changed at a time comes back changed, and alone: no knob writes another's field
  for (const KnobSpec& spec : info().knobs) {
    if (spec.name == "dt") continue;
    SCOPED_TRACE(spec.name);
    Knobs changed = defaults;
    changed[spec.name] = another_value(spec);
    ASSERT_NE(changed[spec.name], spec.default_value);
    Knobs expected = bound;
    expected[spec.name] = changed[spec.name];
    EXPECT_EQ(info().knob_round_trip(changed), expected);
  }
}

// one row of a knob table in docs/backends.md
struct DocumentedKnob {
  std::string name, type, default_text, range_text;
};

// the knob table under the heading "### `<backend>`" of docs/backends.md
std::vector<DocumentedKnob> documented_knobs(const std::string& backend) {
  std::ifstream file(std::string(CHAINMAIL_SOURCE_DIR) + "/docs/backends.md");
  std::string line;
  while (std::getline(file, line) && line != "### `" + backend + "`") {
  }
  std::vector<DocumentedKnob> rows;
  while (std::getline(file, line) && !line.starts_with("| `")) {
  }
  for (; file && line.starts_with("| `"); std::getline(file, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line.substr(1));
    for (std::string cell; std::getline(row, cell, '|');) {
      const auto first = cell.find_first_not_of(' '), last = cell.find_last_not_of(' ');
      cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
    }
    if (cells.size() < 4) break;
    rows.push_back({cells[0].substr(1, cells[0].size() - 2), cells[1], cells[2], cells[3]});
  }
  return rows;
}

// a number as the docs write it: 0.004, 1e-6, 1/2700 ≈ 3.7037e-4, π/2, true, false
double documented_value(std::string text) {
  if (text == "true") return 1.0;
  if (text == "false") return 0.0;
  if (const auto approx = text.find(" ≈"); approx != std::string::npos) text.resize(approx);
  const auto slash = text.find('/');
  const std::string numerator = text.substr(0, slash);
  const double value = numerator == "π" ? std::numbers::pi : std::stod(numerator);
  return slash == std::string::npos ? value : value / std::stod(text.substr(slash + 1));
}

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

TEST_P(KnobTableContract, MatchesTheDocumentedTable) {
  const std::vector<DocumentedKnob> rows = documented_knobs(GetParam());
  ASSERT_EQ(rows.size(), info().knobs.size()) << "docs/backends.md lists another number of knobs";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const KnobSpec& spec = info().knobs[k];
    SCOPED_TRACE(spec.name);
    EXPECT_EQ(rows[k].name, spec.name) << "in the same order";
    EXPECT_EQ(rows[k].type, type_name(spec.type));
    if (spec.type == KnobSpec::Type::choice) {  // the default's name; the range: every name
      EXPECT_EQ(rows[k].default_text, choice_name(spec, spec.default_value));
      std::string names;
      for (const std::string& name : spec.choices)
        names.append(names.empty() ? "`" : ", `").append(name).append("`");
      EXPECT_EQ(rows[k].range_text, names);
      continue;
    }
    EXPECT_EQ(documented_value(rows[k].default_text), spec.default_value);
    if (spec.type == KnobSpec::Type::boolean) continue;  // the range column is empty
    const std::string& range = rows[k].range_text;       // "[min, max] unit"
    const auto comma = range.find(','), close = range.find(']');
    ASSERT_TRUE(range.starts_with("[") && comma < close && close != std::string::npos) << range;
    EXPECT_EQ(documented_value(range.substr(1, comma - 1)), spec.min);
    EXPECT_EQ(documented_value(range.substr(comma + 2, close - comma - 2)), spec.max);
  }
}

std::string backend_name(const ::testing::TestParamInfo<std::string>& info) {
  return info.param;
}

INSTANTIATE_TEST_SUITE_P(Every, KnobTableContract, ::testing::ValuesIn(known_backend_names()),
                         backend_name);

TEST(Registry, ReadsAChoiceKnobByItsNameAndRefusesAnyOtherValueListingTheNames) {
  const BackendInfo& torus = *find_backend("torus_xpbd");
  const KnobSpec& law = *find_knob(torus, "friction_law");
  ASSERT_EQ(law.type, KnobSpec::Type::choice);
  EXPECT_EQ(law.choices, (std::vector<std::string>{"cone", "pyramid"}));
  EXPECT_EQ(resolve_knobs(scene_with(json::object()), torus).at("friction_law"), 0.0);
  for (const std::string name : {"cone", "pyramid"}) {
    const Knobs knobs =
        resolve_knobs(scene_with({{"torus_xpbd", {{"friction_law", name}}}}), torus);
    EXPECT_EQ(choice_name(law, knobs.at("friction_law")), name);
  }
  const std::string key =
      "scene.json: key 'backends.torus_xpbd.friction_law': must be one of "
      "\"cone\", \"pyramid\", got ";
  const std::vector<std::pair<json, std::string>> wrong = {
      {"sphere", "\"sphere\""},
      {"Cone", "\"Cone\""},
      {"", "\"\""},
      {1, "a number"},
      {0.5, "a number"},
      {true, "true"},
      {json::array({"cone"}), "another kind of value"}};
  for (const auto& [value, got] : wrong) {
    SCOPED_TRACE(value.dump());
    try {
      validate_backend_knobs(scene_with({{"torus_xpbd", {{"friction_law", value}}}}));
      FAIL() << "no error";
    } catch (const SceneError& error) {
      EXPECT_EQ(std::string(error.what()), key + got);
    }
  }
  // a name where a number goes is refused as before
  EXPECT_THROW(validate_backend_knobs(scene_with({{"torus_xpbd", {{"friction", "cone"}}}})),
               SceneError);
}

// ---------------------------------------------------------------------------------------------
// backends registered from outside the project

// rings that stay where the rest layout puts them: enough to exercise the registry
class StillBackend final : public Backend {
 public:
  const char* name() const override { return "outside"; }
  void reset(const Scene&, const Weave& weave, const Knobs&) override {
    frame_.resize(weave.size());
    frame_.position = weave.rest_position;
    frame_.orientation = weave.rest_orientation;
    frame_.velocity.setZero();
    frame_.t = 0.0;
  }
  StepStatus step(double dt) override {
    frame_.t += dt;
    return StepStatus::ok;
  }
  void frame(RingFrame& out) const override { out = frame_; }
  const StageProfile& profile() const override { return profile_; }

 private:
  RingFrame frame_;
  StageProfile profile_;
};

BackendInfo still_backend(const std::string& name) {
  BackendInfo info;
  info.name = name;
  info.summary = "rings that never move";
  info.knobs = {{"dt", KnobSpec::Type::number, 0.01, 1e-6, 1.0, "time step, s", {}},
                {"stiffness", KnobSpec::Type::number, 1.0, 0.0, 10.0, "unused, N/m", {}},
                {"passes", KnobSpec::Type::integer, 2, 1, 8, "unused", {}}};
  info.create = [] { return std::make_unique<StillBackend>(); };
  return info;
}

// the message register_backend refuses `info` with ("" when it takes it)
std::string refusal(BackendInfo info) {
  try {
    register_backend(std::move(info));
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(RegisterBackend, AddsABackendThatScenesConfigureAndRunsName) {
  const BackendInfo* plausible = find_backend("plausible");
  const std::size_t known = known_backend_names().size();
  register_backend(still_backend("outside"));

  ASSERT_EQ(known_backend_names().size(), known + 1);
  EXPECT_EQ(known_backend_names().back(), "outside");
  EXPECT_EQ(built_backend_names().back(), "outside");
  EXPECT_TRUE(backend_built("outside"));
  EXPECT_FALSE(backend_known_unbuilt("outside"));
  // lookups handed out before stay valid
  EXPECT_EQ(find_backend("plausible"), plausible);
  EXPECT_EQ(plausible->name, "plausible");
  const BackendInfo* outside = find_backend("outside");
  ASSERT_NE(outside, nullptr);
  EXPECT_STREQ(outside->create()->name(), "outside");

  // a scene sets its knobs like any other backend's, and they are checked alike
  const Knobs knobs = resolve_knobs(scene_with({{"outside", {{"stiffness", 3}}}}), *outside);
  EXPECT_EQ(knobs, (Knobs{{"dt", 0.01}, {"stiffness", 3.0}, {"passes", 2.0}}));
  EXPECT_TRUE(validate_backend_knobs(scene_with({{"outside", json::object()}}, "outside")).empty());
  try {
    validate_backend_knobs(scene_with({{"outside", {{"passes", 9}}}}));
    FAIL() << "no error";
  } catch (const SceneError& error) {
    EXPECT_STREQ(error.what(),
                 "scene.json: key 'backends.outside.passes': must be in [1, 8], got 9");
  }
  test::BackendSim sim("outside", scene_with({{"outside", json::object()}}));
  sim.steps(3);
  EXPECT_DOUBLE_EQ(sim.frame.t, 0.03);
}

TEST(RegisterBackend, RefusesTakenNamesAndBrokenKnobTablesLeavingTheRegistryAsItWas) {
  const std::size_t known = known_backend_names().size();
  const std::string prefix = "register_backend: backend '";
  // every name of the project is taken, built into this binary or not
  for (const std::string name : {"plausible", "massspring", "bullet", "ode"}) {
    const std::string message = refusal(still_backend(name));
    EXPECT_TRUE(message.starts_with(prefix + name + "': the name is taken")) << message;
    EXPECT_EQ(message.find("not built") != std::string::npos, !backend_built(name)) << message;
  }
  for (const std::string name : {"", "all", "none", "Big", "two words", "a.b", "a,b", "9lives"}) {
    EXPECT_EQ(refusal(still_backend(name)),
              prefix + name +
                  "': a name is a word of lowercase letters, digits and '_' starting with a "
                  "letter, and not 'all' or 'none'");
  }
  const auto broken = [&](auto change) {
    BackendInfo info = still_backend("broken");
    change(info);
    return refusal(std::move(info)).substr(prefix.size() + std::string("broken': ").size());
  };
  const std::string no_dt = "needs a knob 'dt' (a number with a positive minimum)";
  EXPECT_EQ(broken([](BackendInfo& i) { i.knobs.erase(i.knobs.begin()); }), no_dt);
  EXPECT_EQ(broken([](BackendInfo& i) { i.knobs[0].min = 0.0; }), no_dt);
  EXPECT_EQ(broken([](BackendInfo& i) { i.knobs[0].type = KnobSpec::Type::integer; }),
            "knob 'dt': an integer knob needs integral min, max and default");
  EXPECT_EQ(broken([](BackendInfo& i) { i.knobs.push_back(i.knobs[1]); }),
            "knob 'stiffness': declared twice");
  EXPECT_EQ(broken([](BackendInfo& i) { i.knobs[1].default_value = 11.0; }),
            "knob 'stiffness': default outside [min, max]");
  EXPECT_EQ(broken([](BackendInfo& i) { i.knobs[1].help.clear(); }),
            "knob 'stiffness': no help text");
  EXPECT_EQ(broken([](BackendInfo& i) { i.knobs[2].max = 8.5; }),
            "knob 'passes': an integer knob needs integral min, max and default");
  EXPECT_EQ(broken([](BackendInfo& i) {
              i.knobs.push_back({"on", KnobSpec::Type::boolean, 1.0, 0.0, 2.0, "a switch", {}});
            }),
            "knob 'on': a boolean knob has range [0, 1] and default 0 or 1");
  const auto with_choice = [](std::vector<std::string> names, double max) {
    return [names, max](BackendInfo& i) {
      i.knobs.push_back({"law", KnobSpec::Type::choice, 0.0, 0.0, max, "a law", names});
    };
  };
  const std::string bad_names =
      "knob 'law': a choice knob needs distinct names, each a plain lowercase word";
  EXPECT_EQ(broken(with_choice({}, -1.0)), "knob 'law': default outside [min, max]");
  EXPECT_EQ(broken(with_choice({"cone", "cone"}, 1.0)), bad_names);
  EXPECT_EQ(broken(with_choice({"cone", "Pyramid"}, 1.0)), bad_names);
  EXPECT_EQ(broken(with_choice({"cone", "pyramid"}, 2.0)),
            "knob 'law': a choice knob has range [0, names - 1] and an integral default");
  EXPECT_EQ(broken([](BackendInfo& i) { i.knobs[1].name = "Stiffness"; }),
            "knob 'Stiffness': not a plain lowercase word");
  EXPECT_EQ(broken([](BackendInfo& i) { i.create = nullptr; }), "create is empty");
  EXPECT_EQ(known_backend_names().size(), known);
  EXPECT_FALSE(backend_known("broken"));
  // and a name registered once is taken
  EXPECT_EQ(refusal(still_backend("second")), "");
  EXPECT_TRUE(refusal(still_backend("second")).starts_with(prefix + "second': the name is taken"));
}

}  // namespace
}  // namespace chainmail
