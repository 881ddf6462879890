#include "renderer/shaders/embedded_shaders.h"

namespace fovlab::shaders {

namespace {
#include "min_filter.spv.h"
#include "sphere_trace.glsl.h"
}  // namespace

const std::span<const uint32_t> min_filter_spirv{min_filter_spirv_words};
const std::string_view sphere_trace_source{sphere_trace_text, sizeof(sphere_trace_text) - 1};

}  // namespace fovlab::shaders
