// glTF materials as the renderer uses them: the metallic-roughness base
// colour (factor times texture, glTF 2.0 §3.9.2), the texture's sampler
// (wrap modes, magnification filter) and the texture coordinates it reads.
#include <tiny_gltf.h>

#include <filesystem>

#include "io/gltf_internal.h"
#include "mbrt/io/texture.h"

namespace mbrt::gltf {
namespace {

TextureWrap wrapOf(int mode) {
  switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TextureWrap::ClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TextureWrap::MirroredRepeat;
    default: return TextureWrap::Repeat;
  }
}

int hexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// A URI's %XX escapes decoded (e.g. "Fox%20Texture.png").
std::string decodeUri(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && hexDigit(uri[i + 1]) >= 0 && hexDigit(uri[i + 2]) >= 0) {
      out += char(hexDigit(uri[i + 1]) * 16 + hexDigit(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// An image file beside the glTF: a relative path without "..", as for
// buffers (gltf_files.h).
std::string imagePath(const Document& doc, const std::string& uri, const std::string& what) {
  const std::filesystem::path rel(decodeUri(uri));
  bool inside = !rel.empty() && rel.is_relative();
  for (const auto& part : rel)
    if (part == "..") inside = false;
  if (!inside) doc.fail(what + ": '" + uri + "' is outside the glTF's folder (image URIs must be relative, without \"..\")");
  return (std::filesystem::path(doc.path).parent_path() / rel).string();
}


}  // namespace

int Materials::texCoordSet(int index) const {
  const tinygltf::Model& m = *doc_->model;
  if (index < 0 || size_t(index) >= m.materials.size()) return -1;
  const tinygltf::TextureInfo& info = m.materials[size_t(index)].pbrMetallicRoughness.baseColorTexture;
  return info.index >= 0 ? info.texCoord : -1;
}

Material Materials::material(int index, SceneDescription& out) {
  const tinygltf::Model& m = *doc_->model;
  Material mat;
  // Without a material: Material{}, as for the other inputs.
  if (index < 0 || size_t(index) >= m.materials.size()) return mat;
  const tinygltf::PbrMetallicRoughness& pbr = m.materials[size_t(index)].pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() >= 3)
    mat.diffuse = {float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]), float(pbr.baseColorFactor[2])};
  if (!isFinite(mat.diffuse)) doc_->fail("material " + std::to_string(index) + ": baseColorFactor is not finite");
  if (pbr.baseColorTexture.index >= 0) mat.texture = texture(pbr.baseColorTexture.index, out);
  return mat;
}

int32_t Materials::texture(int index, SceneDescription& out) {
  const auto found = added_.find(index);
  if (found != added_.end()) return found->second;
  const tinygltf::Model& m = *doc_->model;
  const std::string what = "texture " + std::to_string(index);
  if (size_t(index) >= m.textures.size()) doc_->fail(what + " does not exist");
  const tinygltf::Texture& t = m.textures[size_t(index)];
  if (t.source < 0 || size_t(t.source) >= m.images.size())
    doc_->fail(what + " uses image " + std::to_string(t.source) + " that does not exist");
  const tinygltf::Image& image = m.images[size_t(t.source)];
  const std::string name = doc_->path + ": image " + std::to_string(t.source) + (image.name.empty() ? "" : " '" + image.name + "'");
  Texture tex;
  if (image.bufferView >= 0) {
    tex = decodeTexture(bufferViewBytes(*doc_, image.bufferView, name), name);
  } else if (image.as_is) {
    tex = decodeTexture({image.image.data(), image.image.size()}, name);
  } else {
    if (image.uri.empty()) doc_->fail(what + ": image " + std::to_string(t.source) + " has no data");
    tex = readTexture(imagePath(*doc_, image.uri, name));
  }
  if (t.sampler >= 0) {
    if (size_t(t.sampler) >= m.samplers.size())
      doc_->fail(what + " uses sampler " + std::to_string(t.sampler) + " that does not exist");
    const tinygltf::Sampler& s = m.samplers[size_t(t.sampler)];
    tex.wrapU = wrapOf(s.wrapS);
    tex.wrapV = wrapOf(s.wrapT);
    tex.nearest = s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
  }
  out.textures.push_back(std::move(tex));
  return added_[index] = int32_t(out.textures.size() - 1);
}

std::vector<TexCoord> readTexCoords(const Document& doc, int mesh, int primitive, int set, size_t vertices,
                                    const std::string& what) {
  const tinygltf::Primitive& p = doc.model->meshes[size_t(mesh)].primitives[size_t(primitive)];
  const std::string name = "TEXCOORD_" + std::to_string(set);
  const auto found = p.attributes.find(name);
  if (found == p.attributes.end()) doc.fail(what + " has a base colour texture but no " + name);
  const std::vector<float> f = readFloats(doc, found->second, 2, what + " " + name);
  if (f.size() != 2 * vertices)
    doc.fail(what + " " + name + " has " + std::to_string(f.size() / 2) + " elements for " + std::to_string(vertices) +
             " vertices");
  std::vector<TexCoord> out(vertices);
  for (size_t i = 0; i < vertices; ++i) out[i] = {f[2 * i], f[2 * i + 1]};
  return out;
}

}  // namespace mbrt::gltf
