// EXR output (and input, for tests) through OpenEXR, when built in.
#include <string>

#include "mbrt/io/file_access.h"
#include "mbrt/io/image.h"
#include "mbrt/scene.h"

#ifdef MBRT_HAVE_OPENEXR
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImathBox.h>

#include <exception>
#endif

namespace mbrt {

#ifdef MBRT_HAVE_OPENEXR

bool exrSupported() { return true; }

void writeExr(const std::string& path, const Image& image) {
  if (image.empty()) throw Error("cannot write '" + path + "': empty image");
  const int w = image.width(), h = image.height();
  io::PendingOutput out(path);  // a failed write leaves the old file
  try {
    Imf::Header header(w, h);
    header.channels().insert("R", Imf::Channel(Imf::FLOAT));
    header.channels().insert("G", Imf::Channel(Imf::FLOAT));
    header.channels().insert("B", Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(out.tempPath().c_str(), header);
    Imf::FrameBuffer fb;
    // Rgb is three packed floats: one slice per channel over the same pixels.
    char* base = const_cast<char*>(reinterpret_cast<const char*>(image.pixels().data()));
    const size_t xs = sizeof(Rgb), ys = sizeof(Rgb) * size_t(w);
    fb.insert("R", Imf::Slice(Imf::FLOAT, base + offsetof(Rgb, r), xs, ys));
    fb.insert("G", Imf::Slice(Imf::FLOAT, base + offsetof(Rgb, g), xs, ys));
    fb.insert("B", Imf::Slice(Imf::FLOAT, base + offsetof(Rgb, b), xs, ys));
    file.setFrameBuffer(fb);
    file.writePixels(h);
  } catch (const std::exception& e) {
    throw Error("cannot write '" + path + "': " + e.what());
  }
  out.commit();  // after the OutputFile is closed: the whole file is written
}

Image readExr(const std::string& path) {
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    Image image(w, h);
    char* base = reinterpret_cast<char*>(image.pixels().data());
    const size_t xs = sizeof(Rgb), ys = sizeof(Rgb) * size_t(w);
    // The frame buffer is addressed by absolute pixel coordinates.
    base -= (ptrdiff_t(dw.min.x) * ptrdiff_t(xs) + ptrdiff_t(dw.min.y) * ptrdiff_t(ys));
    Imf::FrameBuffer fb;
    fb.insert("R", Imf::Slice(Imf::FLOAT, base + offsetof(Rgb, r), xs, ys, 1, 1, 0.0));
    fb.insert("G", Imf::Slice(Imf::FLOAT, base + offsetof(Rgb, g), xs, ys, 1, 1, 0.0));
    fb.insert("B", Imf::Slice(Imf::FLOAT, base + offsetof(Rgb, b), xs, ys, 1, 1, 0.0));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return image;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    throw Error("cannot read '" + path + "': " + e.what());
  }
}

#else

namespace {
[[noreturn]] void noExr(const std::string& path) {
  throw Error("cannot use '" + path +
              "': EXR support is not built into this mbrt (install libopenexr-dev, e.g. with "
              "scripts/install-deps.sh, and reconfigure with -DMBRT_WITH_OPENEXR=ON); use a .png file instead");
}
}  // namespace

bool exrSupported() { return false; }
void writeExr(const std::string& path, const Image&) { noExr(path); }
Image readExr(const std::string& path) { noExr(path); }

#endif

}  // namespace mbrt
