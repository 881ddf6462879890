#pragma once
// The runtime side of the OpenXR loader interface (the loader specification's "loader-runtime
// interface negotiation"), which Debian 12's OpenXR 1.0.20 headers do not declare
// (openxr_loader_negotiation.h came with later releases). Declared here from the specification; the
// names are the specification's, so a later header's declarations would be the same types.
#include <openxr/openxr.h>

#include <cstddef>
#include <cstdint>

#if !defined(XR_LOADER_VERSION_1_0)
#define XR_LOADER_VERSION_1_0 1

// The only loader-runtime interface version so far.
#define XR_CURRENT_LOADER_RUNTIME_VERSION 1
// The versions of the two structures exchanged below.
#define XR_LOADER_INFO_STRUCT_VERSION 1
#define XR_RUNTIME_INFO_STRUCT_VERSION 1

extern "C" {

// What plays the part of XrStructureType in the structures of the loader interface.
typedef enum XrLoaderInterfaceStructs {
  XR_LOADER_INTERFACE_STRUCT_UNINTIALIZED = 0,  // sic: the specification's spelling
  XR_LOADER_INTERFACE_STRUCT_LOADER_INFO = 1,
  XR_LOADER_INTERFACE_STRUCT_API_LAYER_REQUEST = 2,
  XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST = 3,
  XR_LOADER_INTERFACE_STRUCT_API_LAYER_CREATE_INFO = 4,
  XR_LOADER_INTERFACE_STRUCT_API_LAYER_NEXT_INFO = 5,
  XR_LOADER_INTERFACE_STRUCTS_MAX_ENUM = 0x7FFFFFFF
} XrLoaderInterfaceStructs;

// In: the interface and API versions the loader can speak.
typedef struct XrNegotiateLoaderInfo {
  XrLoaderInterfaceStructs structType;  // XR_LOADER_INTERFACE_STRUCT_LOADER_INFO
  uint32_t structVersion;               // XR_LOADER_INFO_STRUCT_VERSION
  size_t structSize;                    // sizeof(XrNegotiateLoaderInfo)
  uint32_t minInterfaceVersion;
  uint32_t maxInterfaceVersion;
  XrVersion minApiVersion;
  XrVersion maxApiVersion;
} XrNegotiateLoaderInfo;

// Out: the versions the runtime chose, and its xrGetInstanceProcAddr, through which the loader
// fills its dispatch table.
typedef struct XrNegotiateRuntimeRequest {
  XrLoaderInterfaceStructs structType;  // XR_LOADER_INTERFACE_STRUCT_RUNTIME_REQUEST
  uint32_t structVersion;               // XR_RUNTIME_INFO_STRUCT_VERSION
  size_t structSize;                    // sizeof(XrNegotiateRuntimeRequest)
  uint32_t runtimeInterfaceVersion;
  XrVersion runtimeApiVersion;
  PFN_xrGetInstanceProcAddr getInstanceProcAddr;
} XrNegotiateRuntimeRequest;

// The one symbol a runtime library exports; the loader finds it with dlsym.
typedef XrResult(XRAPI_PTR* PFN_xrNegotiateLoaderRuntimeInterface)(const XrNegotiateLoaderInfo* loaderInfo,
                                                                   XrNegotiateRuntimeRequest* runtimeRequest);
}

#endif  // XR_LOADER_VERSION_1_0
