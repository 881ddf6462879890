#include "renderer/scene/shader_includes.h"

#include <string>

namespace fovlab {

namespace {

// The error result: glslang reports an include whose headerName is empty with headerData as its
// message (after trying includeSystem for a name includeLocal refused).
glslang::TShader::Includer::IncludeResult* refusal(const std::string& header_name) {
  auto* message = new std::string("\"" + header_name +
                                  "\": a shader compiled at run time can include only the renderer's shared headers "
                                  "(renderer/shaders/shared/)");
  return new glslang::TShader::Includer::IncludeResult("", message->data(), message->size(), message);
}

}  // namespace

glslang::TShader::Includer::IncludeResult* SharedHeaderIncluder::includeLocal(const char* header_name,
                                                                              const char* includer_name, size_t) {
  const std::string includer(includer_name ? includer_name : "");
  const size_t slash = includer.rfind('/');
  const std::string relative =
      (slash == std::string::npos ? std::string() : includer.substr(0, slash + 1)) + header_name;
  for (const std::string& name : {relative, std::string(header_name)}) {
    for (const shaders::ShaderHeader& header : headers_) {
      if (header.name == name) return new IncludeResult(name, header.text.data(), header.text.size(), nullptr);
    }
  }
  return refusal(header_name);
}

glslang::TShader::Includer::IncludeResult* SharedHeaderIncluder::includeSystem(const char* header_name, const char*,
                                                                               size_t) {
  return refusal(header_name);  // also after includeLocal refused a quoted name
}

void SharedHeaderIncluder::releaseInclude(IncludeResult* result) {
  if (!result) return;
  delete static_cast<std::string*>(result->userData);
  delete result;
}

}  // namespace fovlab
