#pragma once
namespace ccomp {
/// ccomp's version, as the build sets it (CMake project version).
inline constexpr const char* kVersion = CCOMP_VERSION;
}  // namespace ccomp
