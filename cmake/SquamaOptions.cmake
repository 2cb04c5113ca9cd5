# One INTERFACE target carries the language level, the warnings and the sanitizers;
# every squama target links it privately. Nothing here touches CMAKE_C_FLAGS.
include(CheckCCompilerFlag)
include(CheckCXXCompilerFlag)

add_library(squama_options INTERFACE)
target_compile_features(squama_options INTERFACE c_std_11 cxx_std_17)

set(_sq_c_warnings -Wall -Wextra -Wpedantic -Wshadow -Wstrict-prototypes
    -Wmissing-prototypes -Wvla -Wformat=2 -Wundef)
foreach(flag IN LISTS _sq_c_warnings)
  string(MAKE_C_IDENTIFIER "HAVE_C${flag}" var)
  check_c_compiler_flag(${flag} ${var})
  if(${var})
    target_compile_options(squama_options INTERFACE $<$<COMPILE_LANGUAGE:C>:${flag}>)
  endif()
endforeach()
target_compile_options(squama_options INTERFACE
  $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wshadow>)
# squama never reads errno after a math function: let sqrt and friends be inlined and
# vectorised (not -ffast-math: NaN and infinity keep their meaning)
target_compile_options(squama_options INTERFACE -fno-math-errno)
if(SQUAMA_WERROR)
  target_compile_options(squama_options INTERFACE -Werror)
endif()

if(SQUAMA_SANITIZE)
  set(_sq_san -fsanitize=address,undefined -fno-sanitize-recover=undefined
      -fno-omit-frame-pointer)
  target_compile_options(squama_options INTERFACE ${_sq_san})
  target_link_options(squama_options INTERFACE ${_sq_san})
endif()

if(SQUAMA_FUZZ)
  if(NOT CMAKE_C_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "SQUAMA_FUZZ needs clang (configure with CC=clang CXX=clang++)")
  endif()
  target_compile_options(squama_options INTERFACE -fsanitize=fuzzer-no-link,address,undefined
                         -fno-omit-frame-pointer)
  target_link_options(squama_options INTERFACE -fsanitize=address,undefined)
endif()
