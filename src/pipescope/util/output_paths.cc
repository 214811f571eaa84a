#include "pipescope/util/output_paths.h"

#include "pipescope/util/error.h"

namespace pipescope {
namespace {

std::filesystem::path Resolved(const std::filesystem::path& path) {
  std::error_code error;
  std::filesystem::path resolved =
      std::filesystem::weakly_canonical(std::filesystem::absolute(path, error), error);
  if (error) return std::filesystem::absolute(path).lexically_normal();
  // "out/" and "out" are the same place.
  if (resolved.filename().empty()) resolved = resolved.parent_path();
  return resolved;
}

// True when `inner` is `outer` or lies below it.
bool IsWithin(const std::filesystem::path& inner, const std::filesystem::path& outer) {
  auto inner_part = inner.begin();
  for (const auto& part : outer) {
    if (inner_part == inner.end() || *inner_part != part) return false;
    ++inner_part;
  }
  return true;
}

}  // namespace

void RefuseOutputOverInputs(const std::filesystem::path& output, const std::string& output_flag,
                            const std::vector<NamedInput>& inputs) {
  if (output.empty()) return;
  const std::filesystem::path out = Resolved(output);
  for (const NamedInput& input : inputs) {
    if (input.path.empty()) continue;
    const std::filesystem::path in = Resolved(input.path);
    std::string relation;
    if (out == in) {
      relation = "is";
    } else if (IsWithin(out, in)) {
      relation = "lies inside";
    } else if (IsWithin(in, out)) {
      relation = "holds";
    } else {
      continue;
    }
    throw InputError(output_flag + " " + output.string() + " " + relation + " " + input.name +
                     " (" + input.path.string() +
                     "); an output must not overwrite an input: write it elsewhere");
  }
}

}  // namespace pipescope
