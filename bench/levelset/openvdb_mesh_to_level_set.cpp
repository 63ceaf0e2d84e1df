// See openvdb_mesh_to_level_set.hpp.
#include "openvdb_mesh_to_level_set.hpp"

#include <chrono>

#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

namespace unisph::bench {

OpenVdbLevelSet openvdb_mesh_to_level_set(const std::vector<std::array<float, 3>>& vertices,
                                          const std::vector<std::array<unsigned, 3>>& triangles, float voxel,
                                          float half_width) {
  openvdb::initialize();
  std::vector<openvdb::Vec3s> points;
  points.reserve(vertices.size());
  for (const auto& v : vertices) points.emplace_back(v[0], v[1], v[2]);
  std::vector<openvdb::Vec3I> faces;
  faces.reserve(triangles.size());
  for (const auto& t : triangles) faces.emplace_back(t[0], t[1], t[2]);
  const auto transform = openvdb::math::Transform::createLinearTransform(double(voxel));
  const auto start = std::chrono::steady_clock::now();
  openvdb::FloatGrid::Ptr grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, faces, half_width);
  OpenVdbLevelSet result;
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.active_voxels = std::size_t(grid->activeVoxelCount());
  result.memory_bytes = std::size_t(grid->memUsage());
  return result;
}

}  // namespace unisph::bench
