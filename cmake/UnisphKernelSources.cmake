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
