# unisph_kernel_sources(<source>...)
# Marks sources that launch unisph kernels. Where unisph has its CUDA backend they are compiled
# by nvcc (so the same kernel source also runs on par_device); otherwise by the C++ compiler.
function(unisph_kernel_sources)
  if(UNISPH_HAS_CUDA)
    set_source_files_properties(${ARGN} PROPERTIES LANGUAGE CUDA)
  endif()
endfunction()
