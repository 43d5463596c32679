// A glTF file's clips, meshes and cameras (mbrt/io/gltf.h), for `mbrt info`
// and for the frame range a clip allows.
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>

#include "io/gltf_internal.h"

namespace mbrt {

GltfFileInfo inspectGltf(const std::string& path) {
  const gltf::Document doc = gltf::readDocument(path);
  const tinygltf::Model& m = *doc.model;
  GltfFileInfo info;
  info.nodes = m.nodes.size();
  info.skins = m.skins.size();
  for (size_t i = 0; i < m.animations.size(); ++i) {
    const gltf::Animator anim(doc, int(i));
    GltfClipInfo c;
    c.name = m.animations[i].name;
    c.start = anim.clipStart();
    c.end = anim.clipEnd();
    c.channels = m.animations[i].channels.size();
    info.clips.push_back(c);
  }
  for (const tinygltf::Mesh& mesh : m.meshes) {
    GltfMeshInfo mi;
    mi.name = mesh.name;
    mi.primitives = mesh.primitives.size();
    for (const tinygltf::Primitive& p : mesh.primitives) {
      const auto pos = p.attributes.find("POSITION");
      const size_t vertices = pos == p.attributes.end() ? 0 : gltf::accessorCount(doc, pos->second);
      const size_t indices = p.indices >= 0 ? gltf::accessorCount(doc, p.indices) : vertices;
      const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
      if (mode == TINYGLTF_MODE_TRIANGLES) mi.triangles += indices / 3;
      else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP || mode == TINYGLTF_MODE_TRIANGLE_FAN)
        mi.triangles += indices >= 2 ? indices - 2 : 0;
      mi.vertices += vertices;
      mi.morphTargets = std::max(mi.morphTargets, p.targets.size());
    }
    info.meshes.push_back(mi);
  }
  for (const tinygltf::Node& n : m.nodes)
    if (n.mesh >= 0 && size_t(n.mesh) < info.meshes.size() && n.skin >= 0) info.meshes[size_t(n.mesh)].skinned = true;
  for (const tinygltf::Camera& c : m.cameras) {
    GltfCameraInfo ci;
    ci.name = c.name;
    ci.type = c.type;
    if (c.type == "perspective") ci.yfovDegrees = c.perspective.yfov * 180.0 / 3.14159265358979323846;
    info.cameras.push_back(ci);
  }
  return info;
}

}  // namespace mbrt
