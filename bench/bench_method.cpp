#include "bench/bench_method.h"

#include <stdexcept>
#include <vector>

namespace fovlab::bench {

std::span<const BenchMethodName> bench_method_names() {
  static const std::vector<BenchMethodName> names = [] {
    std::vector<BenchMethodName> list = {{BenchMethod::gt, "gt"}, {BenchMethod::ipr, "ipr"}, {BenchMethod::fipr, "fipr"}};
    for (size_t model = 0; model < kSamplingModelCount; ++model)
      list.push_back({bench_method_of(static_cast<SamplingModel>(model)), kSamplingModelNames[model]});
    return list;
  }();
  return names;
}

const char* bench_method_name(BenchMethod method) {
  for (const BenchMethodName& entry : bench_method_names())
    if (entry.method == method) return entry.name;
  throw std::logic_error("bench: a method without a name");
}

std::optional<BenchMethod> parse_bench_method(std::string_view name) {
  for (const BenchMethodName& entry : bench_method_names())
    if (name == entry.name) return entry.method;
  return std::nullopt;
}

}  // namespace fovlab::bench
