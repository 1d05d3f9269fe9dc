#pragma once
/// \file draw_buffers.h
/// GPU buffers the viewer draws from (RAII, DSA calls): a triangle mesh with per-vertex normal,
/// face index and scalar, and a batch of coloured lines or triangles rebuilt on the CPU.
#include <GL/glcorearb.h>

#include <glm/vec3.hpp>
#include <vector>

#include "gpgpu/program.h"
#include "nurbs/triangle_mesh.h"

namespace viewer {

/// A vertex array object with one interleaved vertex buffer and an optional index buffer. The GL
/// objects are created on the first upload, so that an owner may exist before the context does.
class VertexArray {
 public:
  VertexArray();
  ~VertexArray();
  VertexArray(const VertexArray&) = delete;
  VertexArray& operator=(const VertexArray&) = delete;
  /// Replaces the vertex data: `floats_per_vertex` floats each, attributes `sizes` (in floats) at
  /// locations 0, 1, ... in order.
  void set_vertices(const std::vector<float>& data, const std::vector<int>& sizes);
  void set_indices(const std::vector<unsigned>& indices);
  [[nodiscard]] GLuint id() const { return vao_; }
  [[nodiscard]] long long vertices() const { return vertices_; }
  [[nodiscard]] long long indices() const { return indices_; }

 private:
  void create();
  GLuint vao_ = 0, vbo_ = 0, ebo_ = 0;
  long long vertices_ = 0, indices_ = 0;
};

/// A model's triangles on the GPU (viewer_mesh.vert): position, normal, face, scalar per vertex.
class MeshBuffers {
 public:
  /// Uploads `mesh`; `scalar` (one per vertex, or empty for none) is thickness mode's colour.
  void upload(const nurbs::TriangleMesh& mesh, const std::vector<float>& scalar = {});
  /// Draws every triangle with `program` (already set up: uniforms); binds and unbinds the VAO.
  void draw(const gpgpu::Program& program) const;
  [[nodiscard]] long long triangles() const { return vao_.indices() / 3; }

 private:
  VertexArray vao_;
};

/// Coloured primitives built on the CPU each time they change (viewer_lines.vert).
class LineBatch {
 public:
  void clear();
  void line(const glm::dvec3& a, const glm::dvec3& b, const glm::vec3& color);
  void triangle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::vec3& color);
  /// The 12 edges of the box [lo, hi].
  void box(const glm::dvec3& lo, const glm::dvec3& hi, const glm::vec3& color);
  /// Uploads what changed since the last draw and draws lines, then triangles.
  void draw(const gpgpu::Program& program);
  [[nodiscard]] bool empty() const { return lines_.empty() && triangles_.empty(); }

 private:
  std::vector<float> lines_, triangles_;
  VertexArray line_vao_, triangle_vao_;
  bool dirty_ = true;
};

}  // namespace viewer
