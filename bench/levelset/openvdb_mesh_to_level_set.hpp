#pragma once
// OpenVDB's own mesh-to-level-set (openvdb::tools::meshToLevelSet, float grid) beside ours in
// bench_level_set: a plain interface, so that OpenVDB's headers stay out of the kernel sources
// (those may go through nvcc). Built only where CMake finds OpenVDB (UNISPH_BENCH_HAS_OPENVDB).
#include <array>
#include <cstddef>
#include <vector>

namespace unisph::bench {

struct OpenVdbLevelSet {
  double seconds = 0;              // meshToLevelSet alone (the mesh already in memory)
  std::size_t active_voxels = 0;   // voxels with a value in the narrow band
  std::size_t memory_bytes = 0;    // FloatGrid::memUsage()
};

// vertices: x, y, z; triangles: vertex indices. voxel: the voxel size; half_width in voxels.
OpenVdbLevelSet openvdb_mesh_to_level_set(const std::vector<std::array<float, 3>>& vertices,
                                          const std::vector<std::array<unsigned, 3>>& triangles, float voxel,
                                          float half_width);

}  // namespace unisph::bench
