#include "bench/bench_method.h"

#include <array>
#include <stdexcept>

namespace fovlab::bench {

namespace {

constexpr std::array<BenchMethodName, 7> kNames{{
    {BenchMethod::gt, "gt", std::nullopt},
    {BenchMethod::ipr, "ipr", std::nullopt},
    {BenchMethod::fipr, "fipr", std::nullopt},
    {BenchMethod::rmfr, "rmfr", SamplingModel::rectangular},
    {BenchMethod::hyperbolic, "hyperbolic", SamplingModel::hyperbolic},
    {BenchMethod::linear, "linear", SamplingModel::linear},
    {BenchMethod::kfr, "kfr", SamplingModel::kernel_log_polar},
}};

const BenchMethodName& entry(BenchMethod method) {
  for (const BenchMethodName& name : kNames)
    if (name.method == method) return name;
  throw std::logic_error("bench: a method without a name");
}

}  // namespace

std::span<const BenchMethodName> bench_method_names() { return kNames; }

const char* bench_method_name(BenchMethod method) { return entry(method).name; }

std::optional<BenchMethod> parse_bench_method(std::string_view name) {
  for (const BenchMethodName& entry : kNames)
    if (name == entry.name) return entry.method;
  return std::nullopt;
}

std::optional<SamplingModel> sampling_model_of(BenchMethod method) { return entry(method).sampling_model; }

BenchMethod bench_method_of(SamplingModel model) {
  for (const BenchMethodName& entry : kNames)
    if (entry.sampling_model == model) return entry.method;
  throw std::logic_error("bench: a sampling model without a method");
}

}  // namespace fovlab::bench
