#include "app/output/obj_text.h"

#include <charconv>

namespace wobble {
namespace {

// " x": the shortest decimal that reads back as the same float.
void appendNumber(std::string& out, float x) {
  char buffer[32];
  buffer[0] = ' ';
  const auto end = std::to_chars(buffer + 1, buffer + sizeof buffer, x).ptr;
  out.append(buffer, end);
}

template <typename Vector>
void appendLine(std::string& out, const char* tag, const Vector& v, int components) {
  out += tag;
  for (int k = 0; k < components; ++k) appendNumber(out, float(v[k]));
  out += '\n';
}

}  // namespace

std::string objText(const std::string& name, const SurfaceMesh& mesh, const ObjVertexOrder& order,
                    const SurfaceFrame& frame, const std::string& mtl_file) {
  std::string out = "# wobble: body " + name + "; Y up, metres\nmtllib " + mtl_file + "\no " + name + "\n";
  out.reserve(out.size() + 40 * order.size() + 70 * mesh.vertexCount() + 40 * mesh.triangles.size());
  for (const int v : order.first_vertex) appendLine(out, "v", frame.positions[v], 3);
  for (const Eigen::Vector2f& uv : mesh.uv) appendLine(out, "vt", uv, 2);
  for (const Eigen::Vector3f& n : frame.normals) appendLine(out, "vn", n, 3);
  out += "usemtl " + name + "\ns 1\n";
  for (const auto& triangle : mesh.triangles) {
    out += 'f';
    for (const int v : triangle) {
      const std::string vertex = std::to_string(v + 1);
      out += ' ' + std::to_string(order.line_of[v] + 1) + '/' + vertex + '/' + vertex;
    }
    out += '\n';
  }
  return out;
}

std::string mtlText(const ObjMaterial& m) {
  std::string out = "# wobble: the scene's look of body " + m.name + "\nnewmtl " + m.name + "\n";
  appendLine(out, "Kd", m.color, 3);
  out += m.glossy ? "Ks 0.5 0.5 0.5\nNs 500\nillum 2\n" : "Ks 0 0 0\nillum 1\n";
  if (!m.texture.empty()) out += "map_Kd " + m.texture + "\n";
  return out;
}

}  // namespace wobble
