# unisph_kernel_sources([TARGET <target>] <source>...)
# Marks sources that launch unisph kernels. Where unisph has its CUDA backend they are compiled
# by nvcc (so the same kernel source also runs on par_device); otherwise by the C++ compiler.
# Source properties are per directory: name the TARGET when it was created in another directory
# (the library's module folders add their sources to `unisph`, created at the top).
function(unisph_kernel_sources)
  cmake_parse_arguments(ARG "" "TARGET" "" ${ARGN})
  if(UNISPH_HAS_CUDA)
    if(ARG_TARGET)
      set_source_files_properties(${ARG_UNPARSED_ARGUMENTS} TARGET_DIRECTORY ${ARG_TARGET} PROPERTIES LANGUAGE CUDA)
    else()
      set_source_files_properties(${ARG_UNPARSED_ARGUMENTS} PROPERTIES LANGUAGE CUDA)
    endif()
  endif()
endfunction()

# unisph_uncontracted_kernel_sources([TARGET <target>] <source>...)
# The same, with floating-point contraction off: nvcc fuses a * b + c into one FMA by default
# and the host compiler (x86-64 baseline, no FMA) cannot, so only uncontracted device code
# rounds as seq and par do. For sources whose results must have the same bits on every policy:
# particle generation (level set, seeding, relaxation; docs/particle_generation.md). The host
# side gets -ffp-contract=off too, so that a build with -march=native (FMA) keeps those bits.
function(unisph_uncontracted_kernel_sources)
  unisph_kernel_sources(${ARGN})
  unisph_uncontracted_sources(${ARGN})
endfunction()

# unisph_uncontracted_sources([TARGET <target>] <source>...): the contraction flags alone, for
# sources compiled as CUDA or as host C++ (the tests without their gpu instances).
function(unisph_uncontracted_sources)
  cmake_parse_arguments(ARG "" "TARGET" "" ${ARGN})
  set(scope)
  if(ARG_TARGET)
    set(scope TARGET_DIRECTORY ${ARG_TARGET})
  endif()
  set(options "$<$<COMPILE_LANGUAGE:CUDA>:-fmad=false>")
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    list(APPEND options "$<$<COMPILE_LANGUAGE:CXX>:-ffp-contract=off>" "$<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-ffp-contract=off>")
  endif()
  set_property(SOURCE ${ARG_UNPARSED_ARGUMENTS} ${scope} APPEND PROPERTY COMPILE_OPTIONS ${options})
endfunction()
