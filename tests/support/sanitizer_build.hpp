#pragma once
// AMB_SANITIZER_BUILD: 1 when this translation unit is built with ASan or TSan (gcc's
// __SANITIZE_* macros, clang's __has_feature), else 0. A sanitizer brings its own allocator:
// malloc cannot be interposed there, and glibc's mallopt need not take effect.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define AMB_SANITIZER_BUILD 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define AMB_SANITIZER_BUILD 1
#endif
#endif
#ifndef AMB_SANITIZER_BUILD
#define AMB_SANITIZER_BUILD 0
#endif
