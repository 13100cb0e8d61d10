// gdsmc SDK: version and ABI identity shared by the host and every plugin.
#pragma once
#include <cstdint>

#define GDSMC_VERSION_STRING "0.3.1"
// ABI major: bump on any change to a struct layout or virtual interface in sdk/include/gdsmc.
// ABI minor: bump when something is added that older plugins can ignore (a new optional virtual
// at the end of an interface is NOT such a change: it is a major bump).
#define GDSMC_SDK_ABI_MAJOR 5
#define GDSMC_SDK_ABI_MINOR 0

#if defined(_WIN32)
#define GDSMC_API __declspec(dllexport)
#else
#define GDSMC_API __attribute__((visibility("default")))
#endif

namespace gdsmc {
inline constexpr const char* version_string = GDSMC_VERSION_STRING;
inline constexpr std::uint32_t sdk_abi_major = GDSMC_SDK_ABI_MAJOR;
inline constexpr std::uint32_t sdk_abi_minor = GDSMC_SDK_ABI_MINOR;
}  // namespace gdsmc
