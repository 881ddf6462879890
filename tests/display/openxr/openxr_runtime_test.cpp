// OpenXR without a headset: the Khronos loader loads the test runtime (tests/xr_runtime) named by
// XR_RUNTIME_JSON, with the OpenXR core validation layer on; `fovlab devices` names the runtime, or
// says there is none in one line.
//
// The validation layer of Debian's OpenXR 1.0.20 writes what it finds to stdout, or to the file
// XR_CORE_VALIDATION_FILE_NAME names (XR_CORE_VALIDATION_EXPORT_TYPE=text); it reaches an
// XR_EXT_debug_utils messenger only where the application enables that extension, which the query
// (an instance with no extensions) does not. So every test here points the layer at a file of its
// own, and any text in it fails the test; OpenXrValidationLayer.ReportsAnInvalidCall shows that the
// layer is loaded and that the file catches what it reports.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "display/openxr/openxr_instance.h"
#include "display/openxr/openxr_runtime_info.h"
#include "tests/app/cli_test_support.h"
#include "tests/support/temp_dir.h"
#include "tests/display/openxr/openxr_test_support.h"
#include "tests/xr_runtime/loader_negotiation.h"

namespace fovlab {
namespace {

using test::kValidationLayer;
using test::OpenXrTest;
using test::ScopedEnvironment;

using OpenXrTestRuntime = OpenXrTest;
using OpenXrValidationLayer = OpenXrTest;
using OpenXrDevicesCli = OpenXrTest;

TEST_F(OpenXrTestRuntime, QueryNamesTheRuntimeItsHeadsetViewsAndExtensions) {
  const OpenXrRuntimeInfo info = query_openxr_runtime();
  ASSERT_EQ(info.instance_result, "XR_SUCCESS");
  EXPECT_EQ(info.query_failure, "");
  EXPECT_EQ(info.runtime_name, "fovlab test runtime");
  EXPECT_EQ(info.runtime_version, "0.1.0");
  EXPECT_EQ(info.headset_result, "XR_SUCCESS");
  EXPECT_EQ(info.system_name, "fovlab test HMD (HTC Vive Pro Eye geometry)");
  ASSERT_EQ(info.stereo_eyes.size(), 2u);
  for (const OpenXrEyeImageSize& eye : info.stereo_eyes) {
    EXPECT_EQ(eye.recommended_width_px, 1440u);  // Polychronakis et al. 2023's headset, per eye
    EXPECT_EQ(eye.recommended_height_px, 1600u);
    EXPECT_EQ(eye.max_width_px, 2880u);
    EXPECT_EQ(eye.max_height_px, 3200u);
  }
  EXPECT_TRUE(info.offers_vulkan_enable2);
  EXPECT_TRUE(info.offers_eye_gaze_interaction);
  const std::vector<std::string> expected{
      "OpenXR runtime: fovlab test runtime 0.1.0",
      "  headset: fovlab test HMD (HTC Vive Pro Eye geometry), stereo views 1440x1600, 1440x1600 px (recommended)",
      "  XR_KHR_vulkan_enable2: yes, XR_EXT_eye_gaze_interaction: yes"};
  EXPECT_EQ(describe_openxr_runtime(info), expected);
}

TEST_F(OpenXrTestRuntime, UnpluggedHeadsetIsARuntimeWithoutAHeadset) {
  const ScopedEnvironment unplugged("FOVLAB_TEST_XR_HEADSET", "absent");
  const OpenXrRuntimeInfo info = query_openxr_runtime();
  ASSERT_EQ(info.instance_result, "XR_SUCCESS");
  EXPECT_EQ(info.runtime_name, "fovlab test runtime");
  EXPECT_EQ(info.headset_result, "XR_ERROR_FORM_FACTOR_UNAVAILABLE");
  EXPECT_EQ(info.system_name, "");
  EXPECT_TRUE(info.stereo_eyes.empty());
  EXPECT_EQ(info.query_failure, "");
  EXPECT_TRUE(info.offers_vulkan_enable2);
  const std::vector<std::string> lines = describe_openxr_runtime(info);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[1], "  headset: none connected (XR_ERROR_FORM_FACTOR_UNAVAILABLE)");
}

TEST_F(OpenXrTestRuntime, MissingManifestIsNoRuntime) {
  const ScopedEnvironment missing("XR_RUNTIME_JSON", (scratch_.path() / "missing.json").string());
  const OpenXrRuntimeInfo info = query_openxr_runtime();
  EXPECT_EQ(info.instance_result.rfind("XR_ERROR_", 0), 0u) << info.instance_result;
  EXPECT_EQ(info.runtime_name, "");
  const std::vector<std::string> expected{"OpenXR runtime: none (" + info.instance_result + ")"};
  EXPECT_EQ(describe_openxr_runtime(info), expected);
}

// The specification's rules the query relies on, asked of the runtime through the loader.
TEST_F(OpenXrTestRuntime, KeepsTheTwoCallIdiomThroughTheLoader) {
  OpenXrInstanceResult plain = create_openxr_instance("fovlab", {});
  ASSERT_EQ(openxr_result_name(plain.result), "XR_SUCCESS");
  XrSystemGetInfo get_info{XR_TYPE_SYSTEM_GET_INFO};
  get_info.formFactor = XR_FORM_FACTOR_HANDHELD_DISPLAY;
  XrSystemId system = XR_NULL_SYSTEM_ID;
  EXPECT_EQ(xrGetSystem(plain.instance.handle, &get_info, &system), XR_ERROR_FORM_FACTOR_UNSUPPORTED);
  get_info.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
  ASSERT_EQ(xrGetSystem(plain.instance.handle, &get_info, &system), XR_SUCCESS);
  // One place for two views: the count comes back with XR_ERROR_SIZE_INSUFFICIENT.
  uint32_t count = 0;
  std::vector<XrViewConfigurationView> views(1, XrViewConfigurationView{XR_TYPE_VIEW_CONFIGURATION_VIEW});
  EXPECT_EQ(xrEnumerateViewConfigurationViews(plain.instance.handle, system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO,
                                              1, &count, views.data()),
            XR_ERROR_SIZE_INSUFFICIENT);
  EXPECT_EQ(count, 2u);
  EXPECT_EQ(xrEnumerateViewConfigurationViews(plain.instance.handle, system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_MONO, 0,
                                              &count, nullptr),
            XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
  plain = OpenXrInstanceResult{};  // the loader holds one instance at a time

  // An extension's function, reached through the loader on an instance that enabled the extension
  // (the loader hands out its own entry point either way: the runtime's refusal without the
  // extension is checked below, without the loader).
  OpenXrInstanceResult with_time = create_openxr_instance("fovlab", {"XR_KHR_convert_timespec_time"});
  ASSERT_EQ(openxr_result_name(with_time.result), "XR_SUCCESS");
  PFN_xrVoidFunction function = nullptr;
  ASSERT_EQ(xrGetInstanceProcAddr(with_time.instance.handle, "xrConvertTimespecTimeToTimeKHR", &function), XR_SUCCESS);
  ASSERT_NE(function, nullptr);
  using ConvertTimespec = XrResult(XRAPI_PTR*)(XrInstance, const struct timespec*, XrTime*);
  const timespec when{12, 345};
  XrTime time = 0;
  EXPECT_EQ(reinterpret_cast<ConvertTimespec>(function)(with_time.instance.handle, &when, &time), XR_SUCCESS);
  EXPECT_EQ(time, 12000000345);
  with_time = OpenXrInstanceResult{};
  EXPECT_EQ(openxr_result_name(create_openxr_instance("fovlab", {"XR_FB_not_an_extension"}).result),
            "XR_ERROR_EXTENSION_NOT_PRESENT");
}

// The runtime as the loader meets it, without the loader: the negotiation's checks, what
// xrGetInstanceProcAddr gives before and after an instance, an extension's functions only where
// the instance enabled it, and the checks the validation layer would otherwise make first.
TEST(OpenXrTestRuntimeWithoutLoader, NegotiatesAndDispatchesAsTheSpecificationSays) {
  void* library = dlopen(FOVLAB_TEST_XR_RUNTIME_LIBRARY, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(library, nullptr) << dlerror();
  const auto negotiate =
      reinterpret_cast<PFN_xrNegotiateLoaderRuntimeInterface>(dlsym(library, "xrNegotiateLoaderRuntimeInterface"));
  ASSERT_NE(negotiate, nullptr);
  const XrNegotiateLoaderInfo loader{.structType = XR_LOADER_INTERFACE_STRUCT_LOADER_INFO,
                                     .structVersion = XR_LOADER_INFO_STRUCT_VERSION,
                                     .structSize = sizeof(XrNegotiateLoaderInfo),
                                     .minInterfaceVersion = 1,
                                     .maxInterfaceVersion = XR_CURRENT_LOADER_RUNTIME_VERSION,
                                     .minApiVersion = XR_MAKE_VERSION(1, 0, 0),
                                     .maxApiVersion = XR_CURRENT_API_VERSION};
  const XrNegotiateRuntimeRequest blank{.structType = XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST,
                                        .structVersion = XR_RUNTIME_INFO_STRUCT_VERSION,
                                        .structSize = sizeof(XrNegotiateRuntimeRequest)};
  XrNegotiateRuntimeRequest request = blank;
  request.structSize = sizeof(XrNegotiateRuntimeRequest) - 1;
  EXPECT_EQ(negotiate(&loader, &request), XR_ERROR_INITIALIZATION_FAILED);
  XrNegotiateLoaderInfo newer_interface = loader;
  newer_interface.minInterfaceVersion = newer_interface.maxInterfaceVersion = XR_CURRENT_LOADER_RUNTIME_VERSION + 1;
  request = blank;
  EXPECT_EQ(negotiate(&newer_interface, &request), XR_ERROR_INITIALIZATION_FAILED);
  XrNegotiateLoaderInfo openxr_2 = loader;
  openxr_2.minApiVersion = openxr_2.maxApiVersion = XR_MAKE_VERSION(2, 0, 0);
  EXPECT_EQ(negotiate(&openxr_2, &request), XR_ERROR_INITIALIZATION_FAILED);
  ASSERT_EQ(negotiate(&loader, &request), XR_SUCCESS);
  EXPECT_EQ(request.runtimeInterfaceVersion, 1u);
  EXPECT_EQ(XR_VERSION_MAJOR(request.runtimeApiVersion), 1);
  EXPECT_EQ(XR_VERSION_MINOR(request.runtimeApiVersion), 0);
  const PFN_xrGetInstanceProcAddr get_proc = request.getInstanceProcAddr;
  ASSERT_NE(get_proc, nullptr);
  const auto proc = [&](XrInstance instance, const char* name) {
    PFN_xrVoidFunction function = nullptr;
    const XrResult result = get_proc(instance, name, &function);
    EXPECT_EQ(XR_SUCCEEDED(result), function != nullptr) << name;
    return std::pair{result, function};
  };

  // Before an instance: the global functions only.
  EXPECT_EQ(proc(XR_NULL_HANDLE, "xrGetSystem").first, XR_ERROR_HANDLE_INVALID);
  const auto enumerate_extensions = reinterpret_cast<PFN_xrEnumerateInstanceExtensionProperties>(
      proc(XR_NULL_HANDLE, "xrEnumerateInstanceExtensionProperties").second);
  const auto create = reinterpret_cast<PFN_xrCreateInstance>(proc(XR_NULL_HANDLE, "xrCreateInstance").second);
  ASSERT_NE(enumerate_extensions, nullptr);
  ASSERT_NE(create, nullptr);
  uint32_t count = 0;
  std::vector<XrExtensionProperties> extensions(1, XrExtensionProperties{XR_TYPE_EXTENSION_PROPERTIES});
  EXPECT_EQ(enumerate_extensions(nullptr, 1, &count, extensions.data()), XR_ERROR_SIZE_INSUFFICIENT);
  EXPECT_EQ(count, 3u);
  extensions.assign(3, XrExtensionProperties{XR_TYPE_EXTENSION_PROPERTIES});
  extensions[2].type = XR_TYPE_UNKNOWN;
  EXPECT_EQ(enumerate_extensions(nullptr, 3, &count, extensions.data()), XR_ERROR_VALIDATION_FAILURE);
  EXPECT_EQ(enumerate_extensions("XR_APILAYER_LUNARG_core_validation", 0, &count, nullptr),
            XR_ERROR_API_LAYER_NOT_PRESENT);

  XrInstanceCreateInfo create_info{XR_TYPE_INSTANCE_CREATE_INFO};
  create_info.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
  XrInstance instance = XR_NULL_HANDLE;
  EXPECT_EQ(create(&create_info, &instance), XR_ERROR_NAME_INVALID);  // no application name
  std::strcpy(create_info.applicationInfo.applicationName, "fovlab");
  create_info.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 1, 0);
  EXPECT_EQ(create(&create_info, &instance), XR_ERROR_API_VERSION_UNSUPPORTED);
  create_info.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
  ASSERT_EQ(create(&create_info, &instance), XR_SUCCESS);
  ASSERT_NE(instance, XR_NULL_HANDLE);

  // The instance has no extension enabled: no extension functions; nor what no row serves.
  EXPECT_EQ(proc(instance, "xrConvertTimespecTimeToTimeKHR").first, XR_ERROR_FUNCTION_UNSUPPORTED);
  EXPECT_EQ(proc(instance, "xrApplyHapticFeedback").first, XR_ERROR_FUNCTION_UNSUPPORTED);
  EXPECT_EQ(proc(instance, "xrCreateVulkanInstanceKHR").first, XR_ERROR_FUNCTION_UNSUPPORTED);
  const auto get_system = reinterpret_cast<PFN_xrGetSystem>(proc(instance, "xrGetSystem").second);
  const auto destroy = reinterpret_cast<PFN_xrDestroyInstance>(proc(instance, "xrDestroyInstance").second);
  ASSERT_NE(get_system, nullptr);
  ASSERT_NE(destroy, nullptr);
  XrSystemGetInfo get_info{XR_TYPE_SYSTEM_PROPERTIES};  // the wrong type
  get_info.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
  XrSystemId system = XR_NULL_SYSTEM_ID;
  EXPECT_EQ(get_system(instance, &get_info, &system), XR_ERROR_VALIDATION_FAILURE);
  ASSERT_EQ(destroy(instance), XR_SUCCESS);
  // A destroyed handle stays invalid (handles are never reused).
  EXPECT_EQ(proc(instance, "xrGetSystem").first, XR_ERROR_HANDLE_INVALID);
  EXPECT_EQ(destroy(instance), XR_ERROR_HANDLE_INVALID);
  dlclose(library);
}

// The layer is really on, and what it reports lands in the file the other tests read: a call that
// breaks a valid-usage rule (a structure of the wrong type) is reported.
TEST_F(OpenXrValidationLayer, ReportsAnInvalidCall) {
  {
    OpenXrInstanceResult made = create_openxr_instance("fovlab", {});
    ASSERT_EQ(openxr_result_name(made.result), "XR_SUCCESS");
    XrSystemGetInfo get_info{XR_TYPE_SYSTEM_PROPERTIES};  // should be XR_TYPE_SYSTEM_GET_INFO
    get_info.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
    XrSystemId system = XR_NULL_SYSTEM_ID;
    EXPECT_TRUE(XR_FAILED(xrGetSystem(made.instance.handle, &get_info, &system)));
  }
  EXPECT_NE(validation_report().find("VUID-XrSystemGetInfo-type-type"), std::string::npos) << validation_report();
  expect_no_validation_messages_ = false;
}

TEST_F(OpenXrDevicesCli, NamesTheTestRuntime) {
  const cli_test::CommandResult result = cli_test::run("devices", child_environment(FOVLAB_TEST_XR_RUNTIME_JSON));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("\nOpenXR runtime: fovlab test runtime 0.1.0\n"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("stereo views 1440x1600, 1440x1600 px"), std::string::npos) << result.out;
}

TEST_F(OpenXrDevicesCli, WithoutARuntimeSaysSoInOneLineAndExitsZero) {
  const std::string missing = (scratch_.path() / "missing.json").string();
  const cli_test::CommandResult result = cli_test::run("devices", child_environment(missing));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const size_t line = result.out.find("OpenXR runtime: none (XR_ERROR_");
  ASSERT_NE(line, std::string::npos) << result.out;
  EXPECT_EQ(result.out.find('\n', line) + 1, result.out.size()) << "the last line, and the only OpenXR one";
  EXPECT_EQ(result.out.find("OpenXR"), line);
  EXPECT_EQ(result.err.find("OpenXR-Loader"), std::string::npos) << result.err;  // nor the loader's own lines
}

}  // namespace
}  // namespace fovlab
