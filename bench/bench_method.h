#pragma once
// The methods fovlab bench measures: GT (the reference), IPR and FIPR (Polychronakis et al. 2023),
// and each of Ye et al. 2022's sampling models (core/render_choices.h's SamplingModel, under its
// name). Each is named once, in bench_method_names(): the --methods word (read once, where the flag
// is parsed) and the JSON's "method".
#include <optional>
#include <span>
#include <string_view>

#include "core/render_choices.h"

namespace fovlab::bench {

// In the order a unit's cells are measured.
enum class BenchKind : uint8_t { gt, ipr, fipr, sampling_model };

struct BenchMethod {
  BenchKind kind = BenchKind::gt;
  SamplingModel model = SamplingModel::rectangular;  // sampling_model's own; rectangular for the others
  bool operator==(const BenchMethod&) const = default;

  static const BenchMethod gt, ipr, fipr;
};
inline constexpr BenchMethod BenchMethod::gt{BenchKind::gt};
inline constexpr BenchMethod BenchMethod::ipr{BenchKind::ipr};
inline constexpr BenchMethod BenchMethod::fipr{BenchKind::fipr};

constexpr BenchMethod bench_method_of(SamplingModel model) { return {BenchKind::sampling_model, model}; }
constexpr std::optional<SamplingModel> sampling_model_of(BenchMethod method) {
  if (method.kind == BenchKind::sampling_model) return method.model;
  return std::nullopt;
}

struct BenchMethodName {
  BenchMethod method;
  const char* name;
};

// gt, ipr, fipr, then the sampling models in SamplingModel's order.
std::span<const BenchMethodName> bench_method_names();
const char* bench_method_name(BenchMethod method);
std::optional<BenchMethod> parse_bench_method(std::string_view name);

}  // namespace fovlab::bench
