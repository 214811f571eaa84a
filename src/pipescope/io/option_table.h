#pragma once

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "pipescope/util/error.h"

namespace pipescope {

// One settable key of an Options struct, declared once: its name, unit and help, the range or
// choices it takes (as listed), how a YAML value sets it (range-checked) and how run.json shows
// it. OptionTable below gathers the keys of one Options struct; the helpers Number, Flag, Choice
// and Custom build the keys.
template <typename Options>
struct OptionKey {
  std::string name;
  std::string range;  // "[1, 100]", "x | -x | y | -y", "true | false"
  std::string unit;
  std::string help;
  // Sets the option from `value`; `where` ("FILE: key 'NAME'") starts every error message.
  std::function<void(const YAML::Node& value, const std::string& where, Options*)> set;
  std::function<nlohmann::json(const Options&)> get;
};

// A number in words without a tail of digits: 100000, 0.0005, 1e+06.
std::string FormatOptionNumber(double value);

// Reads `value` as T, or throws InputError "`where` has an invalid value". A bool is also read
// from 1 and 0.
template <typename T>
T ReadOptionValue(const YAML::Node& value, const std::string& where) {
  try {
    if constexpr (std::is_same_v<T, bool>) {
      if (value.IsScalar() && (value.Scalar() == "1" || value.Scalar() == "0")) {
        return value.Scalar() == "1";
      }
    }
    return value.as<T>();
  } catch (const YAML::Exception&) {
    throw InputError(where + " has an invalid value");
  }
}

// Throws InputError "`where` must be in [low, high], got value" unless low <= value <= high
// (a NaN is never in range).
void RequireOptionRange(double value, double low, double high, const std::string& where);

// A number (int, float or double) reached through `member` (a callable that returns a reference
// to it from an Options&), to be within [low, high] in the listed `unit`. The option holds
// `stored_per_unit` times the listed value (1 m per 1000 mm: 0.001), and `also` (callables
// like `member`) receive the same stored value: one key that sets two options.
template <typename Options, typename Member, typename... Also>
OptionKey<Options> ScaledNumber(std::string name, Member member, double low, double high,
                                std::string unit, std::string help, double stored_per_unit,
                                Also... also) {
  using T = std::remove_reference_t<decltype(member(std::declval<Options&>()))>;
  static_assert(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>);
  OptionKey<Options> key;
  key.name = std::move(name);
  key.range = "[" + FormatOptionNumber(low) + ", " + FormatOptionNumber(high) + "]";
  key.unit = std::move(unit);
  key.help = std::move(help);
  key.set = [member, low, high, stored_per_unit, also...](const YAML::Node& node,
                                                          const std::string& where, Options* o) {
    const T value = ReadOptionValue<T>(node, where);
    RequireOptionRange(static_cast<double>(value), low, high, where);
    const T stored = stored_per_unit == 1.0 ? value : static_cast<T>(value * stored_per_unit);
    member(*o) = stored;
    (..., (also(*o) = stored));
  };
  key.get = [member, stored_per_unit](const Options& o) {
    const auto stored = member(const_cast<Options&>(o));
    return stored_per_unit == 1.0 ? nlohmann::json(stored)
                                  : nlohmann::json(stored / stored_per_unit);
  };
  return key;
}

// A number in the unit the option holds (ScaledNumber with a factor of 1).
template <typename Options, typename Member, typename... Also>
OptionKey<Options> Number(std::string name, Member member, double low, double high,
                          std::string unit, std::string help, Also... also) {
  return ScaledNumber<Options>(std::move(name), member, low, high, std::move(unit), std::move(help),
                               1.0, also...);
}

// A true/false switch.
template <typename Options, typename Member>
OptionKey<Options> Flag(std::string name, Member member, std::string help) {
  OptionKey<Options> key;
  key.name = std::move(name);
  key.range = "true | false";
  key.help = std::move(help);
  key.set = [member](const YAML::Node& node, const std::string& where, Options* o) {
    member(*o) = ReadOptionValue<bool>(node, where);
  };
  key.get = [member](const Options& o) { return nlohmann::json(member(const_cast<Options&>(o))); };
  return key;
}

// A string out of `choices`.
template <typename Options, typename Member>
OptionKey<Options> Choice(std::string name, Member member, std::vector<std::string> choices,
                          std::string help) {
  OptionKey<Options> key;
  key.name = std::move(name);
  for (const std::string& choice : choices) key.range += (key.range.empty() ? "" : " | ") + choice;
  key.help = std::move(help);
  key.set = [member, choices, range = key.range](const YAML::Node& node, const std::string& where,
                                                 Options* o) {
    const std::string value = ReadOptionValue<std::string>(node, where);
    if (std::find(choices.begin(), choices.end(), value) == choices.end()) {
      throw InputError(where + " must be " + range + ", got '" + value + "'");
    }
    member(*o) = value;
  };
  key.get = [member](const Options& o) { return nlohmann::json(member(const_cast<Options&>(o))); };
  return key;
}

// A plain member of `Options`, named by its member pointer: a number (any finite value: checks
// that involve several keys are the caller's), a true/false switch, or free text.
template <typename Options, typename T>
OptionKey<Options> Field(std::string name, T Options::*member, std::string help) {
  const auto access = [member](Options& o) -> T& { return o.*member; };
  if constexpr (std::is_same_v<T, bool>) {
    return Flag<Options>(std::move(name), access, std::move(help));
  } else if constexpr (std::is_arithmetic_v<T>) {
    OptionKey<Options> key = Number<Options>(
        std::move(name), access, std::is_signed_v<T> ? std::numeric_limits<double>::lowest() : 0.0,
        std::numeric_limits<double>::max(), "", std::move(help));
    key.range = "finite";
    return key;
  } else {
    static_assert(std::is_same_v<T, std::string>);
    OptionKey<Options> key;
    key.name = std::move(name);
    key.range = "text";
    key.help = std::move(help);
    key.set = [member](const YAML::Node& node, const std::string& where, Options* o) {
      o->*member = ReadOptionValue<std::string>(node, where);
    };
    key.get = [member](const Options& o) { return nlohmann::json(o.*member); };
    return key;
  }
}

// A key whose value is converted on the way in and out (units, enums, optional values, a value
// that sets two options): `set` receives the YAML node and `where`, `get` gives run.json's value.
template <typename Options>
OptionKey<Options> Custom(std::string name, std::string range, std::string unit, std::string help,
                          decltype(OptionKey<Options>::set) set,
                          decltype(OptionKey<Options>::get) get) {
  return {std::move(name), std::move(range), std::move(unit),
          std::move(help), std::move(set),   std::move(get)};
}

// The keys of one Options struct: reads a `--config` YAML map into it, writes it for run.json
// and lists the keys with their defaults for `--list-keys`.
template <typename Options>
class OptionTable {
 public:
  explicit OptionTable(std::vector<OptionKey<Options>> keys) : keys_(std::move(keys)) {}

  const std::vector<OptionKey<Options>>& keys() const { return keys_; }

  // Applies the YAML map in `path` to `options`. An unreadable file, a key that is not in the
  // table, a value of the wrong type or out of range is an InputError naming the file and key.
  void ApplyYamlFile(const std::filesystem::path& path, Options* options) const;

  // Applies an already parsed map; errors name `file` and the key.
  void ApplyYaml(const YAML::Node& root, const std::filesystem::path& file, Options* options) const;

  // Every key's value, as run.json records the options.
  nlohmann::json ToJson(const Options& options) const {
    nlohmann::json json = nlohmann::json::object();
    for (const OptionKey<Options>& key : keys_) json[key.name] = key.get(options);
    return json;
  }

  // The keys, one block each: name, default (from `defaults`), range, unit, help.
  std::string ListKeys(const Options& defaults) const;

 private:
  const OptionKey<Options>* Find(const std::string& name) const {
    for (const OptionKey<Options>& key : keys_) {
      if (key.name == name) return &key;
    }
    return nullptr;
  }

  std::vector<OptionKey<Options>> keys_;
};

// The file's YAML root, which must be a map (an empty file is an empty map); InputError naming
// the file otherwise.
YAML::Node LoadOptionFile(const std::filesystem::path& path);

// The listing of one key (OptionTable::ListKeys).
std::string FormatOptionKey(const std::string& name, const nlohmann::json& value,
                            const std::string& range, const std::string& unit,
                            const std::string& help);

template <typename Options>
void OptionTable<Options>::ApplyYamlFile(const std::filesystem::path& path,
                                         Options* options) const {
  ApplyYaml(LoadOptionFile(path), path, options);
}

template <typename Options>
void OptionTable<Options>::ApplyYaml(const YAML::Node& root, const std::filesystem::path& file,
                                     Options* options) const {
  // Every key is checked before any is applied, so an unknown key leaves `options` as it was.
  for (const auto& entry : root) {
    if (!entry.first.IsScalar()) throw InputError(file.string() + ": a key must be a name");
    const std::string name = entry.first.Scalar();
    if (!Find(name)) {
      std::string known;
      for (const OptionKey<Options>& key : keys_) known += (known.empty() ? "" : ", ") + key.name;
      throw InputError(file.string() + ": unknown key '" + name + "' (valid keys: " + known + ")");
    }
  }
  for (const auto& entry : root) {
    if (entry.second.IsNull()) continue;  // "key:" with no value keeps the default
    const std::string name = entry.first.Scalar();
    Find(name)->set(entry.second, file.string() + ": key '" + name + "'", options);
  }
}

template <typename Options>
std::string OptionTable<Options>::ListKeys(const Options& defaults) const {
  std::string listing;
  for (const OptionKey<Options>& key : keys_) {
    listing += FormatOptionKey(key.name, key.get(defaults), key.range, key.unit, key.help);
  }
  return listing;
}

}  // namespace pipescope
