// Whether this build runs under the address sanitizer: GCC defines __SANITIZE_ADDRESS__, clang
// answers __has_feature. The sanitizer owns malloc, keeps freed blocks in a quarantine and runs
// CPU work two to three times slower, so what measures memory or CPU time asks here.
#pragma once

#if defined(__SANITIZE_ADDRESS__)
#define QUANTUM_ADDRESS_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define QUANTUM_ADDRESS_SANITIZED 1
#endif
#endif
#ifndef QUANTUM_ADDRESS_SANITIZED
#define QUANTUM_ADDRESS_SANITIZED 0
#endif

namespace quantum::system {

inline constexpr bool kAddressSanitized = QUANTUM_ADDRESS_SANITIZED;

}  // namespace quantum::system
