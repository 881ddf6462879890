#pragma once
// The methods fovlab bench measures, each named once: the table below maps each to its --methods
// word (read once, where the flag is parsed) and, for Ye et al. 2022's sampling models, to the
// model it renders.
#include <optional>
#include <span>
#include <string_view>

#include "foveation/sampling_map.h"

namespace fovlab::bench {

// In the order a unit's cells are measured: GT (the reference), IPR, FIPR (Polychronakis et al.
// 2023), the sampling models.
enum class BenchMethod { gt, ipr, fipr, rmfr, hyperbolic, linear, kfr };

struct BenchMethodName {
  BenchMethod method;
  const char* name;                             // its word in --methods and in the JSON's "method"
  std::optional<SamplingModel> sampling_model;  // the sampling models' own
};

std::span<const BenchMethodName> bench_method_names();
const char* bench_method_name(BenchMethod method);
std::optional<BenchMethod> parse_bench_method(std::string_view name);
std::optional<SamplingModel> sampling_model_of(BenchMethod method);
BenchMethod bench_method_of(SamplingModel model);

}  // namespace fovlab::bench
