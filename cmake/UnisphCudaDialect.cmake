# CMake 3.25 predates nvcc 13 and does not know its C++20 flag, so a target that requires
# cxx_std_20 (unisph::unisph does) fails to configure with "requires the language dialect
# CUDA20". This teaches CMake the flag. Call after enable_language(CUDA).
macro(unisph_teach_cuda_dialect)
  if(CMAKE_CUDA_COMPILER AND NOT CMAKE_CUDA20_STANDARD_COMPILE_OPTION)
    set(CMAKE_CUDA20_STANDARD_COMPILE_OPTION "-std=c++20")
    set(CMAKE_CUDA20_EXTENSION_COMPILE_OPTION "-std=c++20")
    list(APPEND CMAKE_CUDA_COMPILE_FEATURES cuda_std_20)
  endif()
endmacro()
