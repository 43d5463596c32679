// Reading a glTF file with tinygltf, and reading its accessors.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "io/gltf_files.h"
#include "io/gltf_internal.h"

namespace mbrt::gltf {

// A buffer view's bytes, checked: the view and its buffer exist and the view
// fits the buffer. `what` names it in errors.
std::span<const uint8_t> bufferViewBytes(const Document& doc, int viewIndex, const std::string& what) {
  const tinygltf::Model& m = *doc.model;
  if (viewIndex < 0 || size_t(viewIndex) >= m.bufferViews.size())
    doc.fail(what + ": buffer view " + std::to_string(viewIndex) + " does not exist");
  const tinygltf::BufferView& view = m.bufferViews[size_t(viewIndex)];
  if (view.buffer < 0 || size_t(view.buffer) >= m.buffers.size())
    doc.fail(what + ": buffer " + std::to_string(view.buffer) + " does not exist");
  const std::vector<unsigned char>& data = m.buffers[size_t(view.buffer)].data;
  if (view.byteOffset > data.size() || view.byteLength > data.size() - view.byteOffset)
    doc.fail(what + ": buffer view " + std::to_string(viewIndex) + " does not fit its buffer: truncated or corrupt file");
  return {data.data() + view.byteOffset, view.byteLength};
}

namespace {

// tinygltf's file access, guarded (gltf_files.h); it never writes.
tinygltf::FsCallbacks guardedFileCallbacks(const ExternalBufferRules& rules) {
  tinygltf::FsCallbacks fs{};
  fs.FileExists = [](const std::string& path, void*) { return fileExists(path); };
  fs.ExpandFilePath = [](const std::string& path, void*) { return path; };  // no ~ or $VAR expansion
  fs.ReadWholeFile = [](std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
    std::string why;
    if (readExternalBuffer(*static_cast<const ExternalBufferRules*>(user), path, *out, why)) return true;
    if (err) *err += why;
    return false;
  };
  fs.WriteWholeFile = [](std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "mbrt never writes glTF files";
    return false;
  };
  fs.user_data = const_cast<ExternalBufferRules*>(&rules);
  return fs;
}

// Images are decoded only when a material uses one (gltf_materials.cpp
// reads buffer views and files there); the bytes of an embedded data URI
// exist only now, so they are kept as they are.
bool keepImageBytes(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                    const unsigned char* bytes, int size, void*) {
  if (image->bufferView < 0 && bytes && size > 0) {
    image->image.assign(bytes, bytes + size);
    image->as_is = true;
  }
  return true;
}

double normalizedValue(const unsigned char* p, int componentType, bool normalized) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: { float v; std::memcpy(&v, p, 4); return v; }
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: { double v; std::memcpy(&v, p, 8); return v; }
    case TINYGLTF_COMPONENT_TYPE_BYTE: { const double v = int8_t(*p); return normalized ? std::max(v / 127.0, -1.0) : v; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: { const double v = *p; return normalized ? v / 255.0 : v; }
    case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t s; std::memcpy(&s, p, 2); return normalized ? std::max(s / 32767.0, -1.0) : s; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t s; std::memcpy(&s, p, 2); return normalized ? s / 65535.0 : s; }
    case TINYGLTF_COMPONENT_TYPE_INT: { int32_t s; std::memcpy(&s, p, 4); return s; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t s; std::memcpy(&s, p, 4); return s; }
  }
  return 0.0;
}

// Reads `count` elements of `components` values at view + offset into out.
void readElements(const Document& doc, int viewIndex, size_t offset, int componentType, bool normalized,
                  size_t count, int components, const std::string& what, double* out) {
  const std::span<const uint8_t> bytes = bufferViewBytes(doc, viewIndex, what);  // checked
  const tinygltf::BufferView& view = doc.model->bufferViews[size_t(viewIndex)];
  const int componentSize = tinygltf::GetComponentSizeInBytes(uint32_t(componentType));
  if (componentSize <= 0) doc.fail(what + ": unknown component type " + std::to_string(componentType));
  const size_t elementSize = size_t(componentSize) * size_t(components);
  const size_t stride = view.byteStride ? view.byteStride : elementSize;
  if (count == 0) return;
  // Every size comes from the file: check without overflowing size_t.
  const bool elementsFit = offset <= view.byteLength && elementSize <= view.byteLength - offset &&
                           (count - 1) <= (view.byteLength - offset - elementSize) / stride;
  const size_t need = elementsFit ? offset + (count - 1) * stride + elementSize : size_t(-1);
  if (!elementsFit)
    doc.fail(what + ": needs " + std::to_string(need) + " bytes of buffer view " + std::to_string(viewIndex) +
             ", which has " + std::to_string(view.byteLength) + ": truncated or corrupt file");
  const unsigned char* base = bytes.data() + offset;
  for (size_t i = 0; i < count; ++i)
    for (int c = 0; c < components; ++c)
      out[i * size_t(components) + size_t(c)] =
          normalizedValue(base + i * stride + size_t(c) * size_t(componentSize), componentType, normalized);
}

std::vector<double> readAccessor(const Document& doc, int index, int components, const std::string& what) {
  const tinygltf::Model& m = *doc.model;
  if (index < 0 || size_t(index) >= m.accessors.size())
    doc.fail(what + ": accessor " + std::to_string(index) + " does not exist");
  const tinygltf::Accessor& a = m.accessors[size_t(index)];
  const int n = tinygltf::GetNumComponentsInType(uint32_t(a.type));
  if (n != components)
    doc.fail(what + ": accessor " + std::to_string(index) + " has " + std::to_string(n) +
             " components per element, expected " + std::to_string(components));
  // An accessor without a buffer view is all zeros (or sparse): its count is
  // bounded only by this limit; one with a view by the view's size (checked
  // in readElements before anything is allocated).
  constexpr size_t kMaxElements = size_t(1) << 26;
  if (a.count > kMaxElements)
    doc.fail(what + ": accessor " + std::to_string(index) + " has " + std::to_string(a.count) +
             " elements, more than the limit of " + std::to_string(kMaxElements));
  if (a.sparse.isSparse && (a.sparse.count < 0 || size_t(a.sparse.count) > a.count))
    doc.fail(what + ": accessor " + std::to_string(index) + " has a bad sparse count");
  std::vector<double> out(a.count * size_t(components), 0.0);
  if (a.bufferView >= 0)
    readElements(doc, a.bufferView, a.byteOffset, a.componentType, a.normalized, a.count, components, what, out.data());
  if (a.sparse.isSparse) {
    const size_t sc = size_t(a.sparse.count);
    std::vector<double> idx(sc), vals(sc * size_t(components));
    readElements(doc, a.sparse.indices.bufferView, size_t(a.sparse.indices.byteOffset), a.sparse.indices.componentType,
                 false, sc, 1, what + " (sparse indices)", idx.data());
    readElements(doc, a.sparse.values.bufferView, size_t(a.sparse.values.byteOffset), a.componentType, a.normalized,
                 sc, components, what + " (sparse values)", vals.data());
    for (size_t i = 0; i < sc; ++i) {
      if (idx[i] < 0 || idx[i] >= double(a.count)) doc.fail(what + ": sparse index out of range");
      for (int c = 0; c < components; ++c)
        out[size_t(idx[i]) * size_t(components) + size_t(c)] = vals[i * size_t(components) + size_t(c)];
    }
  }
  return out;
}

}  // namespace

void Document::fail(const std::string& what) const { throw Error(path + ": " + what); }

Document readDocument(const std::string& path) {
  Document doc;
  doc.path = path;
  const std::vector<unsigned char> bytes = readRegularFile(path);
  const bool glb = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  const ExternalBufferRules rules = externalBufferRules(path, bytes, glb);
  doc.model = std::make_shared<tinygltf::Model>();
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&keepImageBytes, nullptr);
  loader.SetFsCallbacks(guardedFileCallbacks(rules));
  std::string err, warn;
  bool ok = false;
  if (bytes.empty()) doc.fail("not a valid glTF file: the file is empty");
  if (bytes.size() > std::numeric_limits<unsigned int>::max()) doc.fail("not a valid glTF file: larger than 4 GiB");
  const auto size = static_cast<unsigned int>(bytes.size());
  try {
    ok = glb ? loader.LoadBinaryFromMemory(doc.model.get(), &err, &warn, bytes.data(), size, rules.folder)
             : loader.LoadASCIIFromString(doc.model.get(), &err, &warn, reinterpret_cast<const char*>(bytes.data()),
                                          size, rules.folder);
  } catch (const std::exception& e) {
    doc.fail(std::string("not a valid glTF file (") + e.what() + ")");
  }
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    for (char& c : err)
      if (c == '\n') c = ';';
    doc.fail("not a valid glTF file: " + (err.empty() ? std::string("unknown error") : err));
  }
  return doc;
}

size_t accessorCount(const Document& doc, int index) {
  if (index < 0 || size_t(index) >= doc.model->accessors.size())
    doc.fail("accessor " + std::to_string(index) + " does not exist");
  return doc.model->accessors[size_t(index)].count;
}

std::vector<float> readFloats(const Document& doc, int accessor, int components, const std::string& what) {
  const std::vector<double> d = readAccessor(doc, accessor, components, what);
  std::vector<float> out(d.size());
  for (size_t i = 0; i < d.size(); ++i) {
    out[i] = float(d[i]);
    if (!std::isfinite(out[i]) || std::fabs(out[i]) > kMaxCoordinate)
      doc.fail(what + ": element " + std::to_string(i / size_t(components)) + " is not finite (" +
               std::to_string(d[i]) + ")");
  }
  return out;
}

std::vector<uint32_t> readUints(const Document& doc, int accessor, int components, const std::string& what) {
  const std::vector<double> d = readAccessor(doc, accessor, components, what);
  std::vector<uint32_t> out(d.size());
  for (size_t i = 0; i < d.size(); ++i) {
    if (!(d[i] >= 0 && d[i] <= 4294967295.0 && d[i] == std::floor(d[i])))
      doc.fail(what + ": element " + std::to_string(i / size_t(components)) + " is not a valid index");
    out[i] = uint32_t(d[i]);
  }
  return out;
}

}  // namespace mbrt::gltf
