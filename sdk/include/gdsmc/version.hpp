// gdsmc SDK: version and ABI identity shared by the host and every plugin.
#pragma once
#include <cstdint>

#define GDSMC_VERSION_STRING "0.4.0"
// ABI major: bump on a change that breaks built plugins: a field of a host-owned struct moved or
// removed, a frozen struct changed, a virtual of a plugin interface added, removed or changed
// (see "How the contract grows" in plugin.hpp).
// ABI minor: bump when something is added that older plugins can ignore: a field at the end of a
// host-owned struct, an extension id (PluginObject::extension), a virtual appended to OutputSink.
// A plugin built against a newer minor than the host's is refused.
#define GDSMC_SDK_ABI_MAJOR 6
#define GDSMC_SDK_ABI_MINOR 6

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
