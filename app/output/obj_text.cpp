#include "app/output/obj_text.h"

#include <charconv>
#include <string>

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

std::string objHeader(const std::string& name, const std::string& mtl_file) {
  return "# wobble: body " + name + "; Y up, metres\nmtllib " + mtl_file + "\no " + name + "\n";
}

std::string objMaterialUse(const std::string& name) { return "usemtl " + name + "\ns 1\n"; }

}  // namespace

std::string objText(const std::string& name, const SurfaceMesh& mesh, const ObjVertexOrder& order,
                    const SurfaceFrame& frame, const std::string& mtl_file) {
  std::string out = objHeader(name, mtl_file);
  out.reserve(out.size() + 40 * order.size() + 70 * mesh.vertexCount() + 40 * mesh.triangles.size());
  for (const int v : order.first_vertex) appendLine(out, "v", frame.positions[v], 3);
  for (const Eigen::Vector2f& uv : mesh.uv) appendLine(out, "vt", uv, 2);
  for (const Eigen::Vector3f& n : frame.normals) appendLine(out, "vn", n, 3);
  out += objMaterialUse(name);
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

std::uint64_t objTextSizeBound(const std::string& name, const SurfaceMesh& mesh, const ObjVertexOrder& order,
                               const std::string& mtl_file) {
  constexpr std::uint64_t kLongestNumber = 1 + 15;  // " " and the longest shortest-round-trip float
  const auto digits = [](std::uint64_t n) {
    std::uint64_t d = 1;
    for (; n >= 10; n /= 10) ++d;
    return d;
  };
  std::uint64_t bytes = objHeader(name, mtl_file).size() + objMaterialUse(name).size();
  bytes += std::uint64_t(order.size()) * (1 + 3 * kLongestNumber + 1);        // v x y z
  bytes += std::uint64_t(mesh.vertexCount()) * (2 + 3 * kLongestNumber + 1);  // vn x y z
  std::string vt;
  for (const Eigen::Vector2f& uv : mesh.uv) appendLine(vt, "vt", uv, 2);  // fixed: exactly as written
  bytes += vt.size();
  for (const auto& triangle : mesh.triangles) {
    bytes += 2;                                                                                  // "f" and the newline
    for (const int v : triangle) bytes += 3 + digits(order.line_of[v] + 1) + 2 * digits(v + 1);  // " a/b/b"
  }
  return bytes;
}

std::string mtlText(const ObjMaterial& m) {
  std::string out = "# wobble: the scene's look of body " + m.name + "\nnewmtl " + m.name + "\n";
  appendLine(out, "Kd", m.color, 3);
  out += m.glossy ? "Ks 0.5 0.5 0.5\nNs 500\nillum 2\n" : "Ks 0 0 0\nillum 1\n";
  if (!m.texture.empty()) out += "map_Kd " + m.texture + "\n";
  return out;
}

}  // namespace wobble
