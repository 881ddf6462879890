#pragma once
// The #include resolver of the shaders compiled at run time (glslang's TShader::Includer): it serves
// the headers that C++ and GLSL share (renderer/shaders/shared/, embedded in the binary) by the
// names they are included by, and refuses any other name with a message saying so.
#include <glslang/Public/ShaderLang.h>

#include <span>

#include "renderer/shaders/embedded_shaders.h"

namespace fovlab {

class SharedHeaderIncluder : public glslang::TShader::Includer {
 public:
  explicit SharedHeaderIncluder(std::span<const shaders::ShaderHeader> headers) : headers_(headers) {}

  // "name" relative to the including file's folder ("gpu_types.h" in "shared/fipr_params.h"), else as given.
  IncludeResult* includeLocal(const char* header_name, const char* includer_name, size_t depth) override;
  IncludeResult* includeSystem(const char* header_name, const char* includer_name, size_t depth) override;
  void releaseInclude(IncludeResult* result) override;

 private:
  std::span<const shaders::ShaderHeader> headers_;
};

}  // namespace fovlab
