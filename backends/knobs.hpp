// Backend knobs: the tunables a scene sets under backends.<name>, and the table through which a
// backend declares each of them once, bound to the settings field it fills.
#pragma once

#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace chainmail {

// one tunable of a backend, as it appears under backends.<name> in the scene file
struct KnobSpec {
  // choice: one of the names in `choices`, written as the name, held in Knobs as its index
  enum class Type { number, integer, boolean, choice };
  std::string name;
  Type type = Type::number;
  double default_value = 0.0;
  double min = 0.0;                  // inclusive
  double max = 0.0;                  // inclusive
  std::string help;                  // one line, for `chainmail backends` and the schema
  std::vector<std::string> choices;  // (choice) the names, in index order
  std::string unit = {};  // of the value and range ("s", "N/m", "rad"); empty: a pure number
  std::string doc = {};   // the meaning in docs/backends.md (Markdown); empty: the help
};

// resolved knob values (booleans as 0/1, choices as the index of the name), every spec'd knob
// present
using Knobs = std::map<std::string, double>;

// the value of one resolved knob; throws std::out_of_range naming it when it is absent
inline double knob_value(const Knobs& knobs, const std::string& name) {
  const auto it = knobs.find(name);
  if (it == knobs.end()) throw std::out_of_range("knob '" + name + "' was not resolved");
  return it->second;
}

// the name a choice knob's resolved value (its index) stands for; throws std::out_of_range
inline const std::string& choice_name(const KnobSpec& spec, double index) {
  if (!(index >= 0.0 && index < static_cast<double>(spec.choices.size())))
    throw std::out_of_range("knob '" + spec.name + "': no choice " + std::to_string(index));
  return spec.choices[static_cast<std::size_t>(index)];
}

// A backend's knob table. Each knob is declared once, bound to a field of the settings struct S
// that reset() fills, with its default read from a default-constructed S; the spec list of
// BackendInfo and the fill of S come from the same entries, so they cannot disagree.
//
//   KnobTable<PlausibleSettings> t;
//   t.time_step(0.004, 1e-6, 0.1, "time step, s");
//   t.integer("iterations", &PlausibleSettings::iterations, 1, 100000, "sweeps per step");
//   t.boolean("swivel", &PlausibleSettings::swivel, "swivel rings into the 4-in-1 pattern");
//   t.choice("law", &Settings::law, {"cone", "pyramid"}, "friction law");  // an enum field
//   info.knobs = t.specs();                         // in <name>_backend_info()
//   const PlausibleSettings s = t.settings(knobs);  // in reset()
//
// `dt` is a knob of every backend (the harness steps with it) but a field of no settings struct:
// it reaches a model through step(dt) (an adapter that needs it in reset reads the resolved knob,
// as massspring does for the initial velocity). time_step() declares it, unbound, with its
// default written there once. Knobs appear in the order they are declared.
template <class S>
class KnobTable {
 public:
  KnobTable& time_step(double default_value, double min, double max, std::string help) {
    return add({"dt", KnobSpec::Type::number, default_value, min, max, std::move(help), {}}, {});
  }
  KnobTable& number(std::string name, double S::*field, double min, double max, std::string help) {
    const double value = S{}.*field;
    return add({std::move(name), KnobSpec::Type::number, value, min, max, std::move(help), {}},
               field);
  }
  KnobTable& integer(std::string name, int S::*field, int min, int max, std::string help) {
    const double value = S{}.*field;
    return add({std::move(name),
                KnobSpec::Type::integer,
                value,
                double(min),
                double(max),
                std::move(help),
                {}},
               field);
  }
  KnobTable& boolean(std::string name, bool S::*field, std::string help) {
    const double value = S{}.*field ? 1.0 : 0.0;
    return add({std::move(name), KnobSpec::Type::boolean, value, 0.0, 1.0, std::move(help), {}},
               field);
  }

  // an enum field whose values 0, 1, ... are named by `names`
  template <class E>
  KnobTable& choice(std::string name, E S::*field, std::vector<std::string> names,
                    std::string help) {
    static_assert(std::is_enum_v<E>, "a choice knob fills an enum field");
    const double value = static_cast<double>(S{}.*field);
    const double last = static_cast<double>(names.size()) - 1.0;
    Accessor access{[field](S& s, double v) { s.*field = static_cast<E>(static_cast<int>(v)); },
                    [field](const S& s) { return static_cast<double>(s.*field); }};
    return add({std::move(name), KnobSpec::Type::choice, value, 0.0, last, std::move(help),
                std::move(names)},
               std::move(access));
  }

  // the unit and the documented meaning of the knob declared last (scripts/knob_docs.py writes
  // docs/backends.md's knob tables from them):  t.number(...).unit("N/m").doc("...");
  KnobTable& unit(std::string unit) {
    specs_.back().unit = std::move(unit);
    return *this;
  }
  KnobTable& doc(std::string doc) {
    specs_.back().doc = std::move(doc);
    return *this;
  }

  const std::vector<KnobSpec>& specs() const { return specs_; }

  // every bound field of `settings` from resolved knobs (integers truncated, booleans non-zero)
  void apply(const Knobs& knobs, S& settings) const {
    for (std::size_t k = 0; k < specs_.size(); ++k) {
      if (std::holds_alternative<std::monostate>(fields_[k])) continue;
      const double value = knob_value(knobs, specs_[k].name);
      std::visit(Assign{settings, value}, fields_[k]);
    }
  }
  S settings(const Knobs& knobs) const {
    S settings{};
    apply(knobs, settings);
    return settings;
  }
  // the knob values `settings` holds in its bound fields (unbound knobs such as dt left out)
  Knobs read(const S& settings) const {
    Knobs values;
    for (std::size_t k = 0; k < specs_.size(); ++k) {
      if (std::holds_alternative<std::monostate>(fields_[k])) continue;
      values[specs_[k].name] = std::visit(Read{settings}, fields_[k]);
    }
    return values;
  }
  // resolved knobs -> a default S filled by apply() -> read(): what BackendInfo::knob_round_trip
  // holds, so that tests reach every backend's binding through the registry
  std::function<Knobs(const Knobs&)> round_trip() const {
    return [table = *this](const Knobs& knobs) { return table.read(table.settings(knobs)); };
  }

 private:
  // an enum field, reached through its conversions to and from the index
  struct Accessor {
    std::function<void(S&, double)> set;
    std::function<double(const S&)> get;
  };
  using Field = std::variant<std::monostate, double S::*, int S::*, bool S::*, Accessor>;

  struct Assign {
    S& settings;
    double value;
    void operator()(std::monostate) const {}
    void operator()(double S::*f) const { settings.*f = value; }
    void operator()(int S::*f) const { settings.*f = static_cast<int>(value); }
    void operator()(bool S::*f) const { settings.*f = value != 0.0; }
    void operator()(const Accessor& f) const { f.set(settings, value); }
  };
  struct Read {
    const S& settings;
    double operator()(std::monostate) const { return 0.0; }
    double operator()(double S::*f) const { return settings.*f; }
    double operator()(int S::*f) const { return settings.*f; }
    double operator()(bool S::*f) const { return settings.*f ? 1.0 : 0.0; }
    double operator()(const Accessor& f) const { return f.get(settings); }
  };

  KnobTable& add(KnobSpec spec, Field field) {
    specs_.push_back(std::move(spec));
    fields_.push_back(std::move(field));
    return *this;
  }

  std::vector<KnobSpec> specs_;
  std::vector<Field> fields_;  // (knobs) the field each spec fills; monostate for dt
};

}  // namespace chainmail
