// Part of embree_side.inl: wrong calls, each on a fresh device with an
// error callback, and what each build of the API reported. Only calls the
// real libembree3 survives (it asserts or crashes on some others, which
// mbrt reports instead: test_errors.cpp).

struct Recorder {
  int calls = 0;
  std::string message;
};

void recordError(void* user, RTCError, const char* message) {
  auto* r = static_cast<Recorder*>(user);
  ++r->calls;
  r->message = message ? message : "";
}

template <class F>
Mistake attempt(const char* what, F&& f) {
  RTCDevice d = rtcNewDevice(nullptr);
  Recorder rec;
  rtcSetDeviceErrorFunction(d, recordError, &rec);
  rtcGetDeviceError(nullptr);  // clears the thread's code
  RTCGeometry tri = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_TRIANGLE);
  RTCGeometry inst = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_INSTANCE);
  RTCScene scene = rtcNewScene(d);
  f(d, tri, inst, scene);
  Mistake m{what, rtcGetDeviceError(d), rtcGetDeviceError(nullptr), rec.calls, rec.message};
  rtcReleaseScene(scene);
  rtcReleaseGeometry(inst);
  rtcReleaseGeometry(tri);
  rtcReleaseDevice(d);
  return m;
}

std::vector<Mistake> mistakes() {
  static const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  static char memory[64];
  std::vector<Mistake> out;
  out.push_back(attempt("unknown geometry type", [](RTCDevice d, auto, auto, auto) {
    rtcNewGeometry(d, RTCGeometryType(77));
  }));
  out.push_back(attempt("UINT3 vertex buffer", [](auto, RTCGeometry t, auto, auto) {
    rtcSetNewGeometryBuffer(t, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_UINT3, 12, 3);
  }));
  out.push_back(attempt("FLOAT3 index buffer", [](auto, RTCGeometry t, auto, auto) {
    rtcSetNewGeometryBuffer(t, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_FLOAT3, 12, 3);
  }));
  out.push_back(attempt("index buffer slot 1", [](auto, RTCGeometry t, auto, auto) {
    rtcSetNewGeometryBuffer(t, RTC_BUFFER_TYPE_INDEX, 1, RTC_FORMAT_UINT3, 12, 3);
  }));
  out.push_back(attempt("vertex slot beyond the time steps", [](auto, RTCGeometry t, auto, auto) {
    rtcSetNewGeometryBuffer(t, RTC_BUFFER_TYPE_VERTEX, 1, RTC_FORMAT_FLOAT3, 12, 3);
  }));
  out.push_back(attempt("normal buffer on triangles", [](auto, RTCGeometry t, auto, auto) {
    rtcSetNewGeometryBuffer(t, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, 12, 3);
  }));
  out.push_back(attempt("vertex attribute slot 0 of 0", [](auto, RTCGeometry t, auto, auto) {
    rtcSetNewGeometryBuffer(t, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, 0, RTC_FORMAT_FLOAT3, 12, 3);
  }));
  out.push_back(attempt("misaligned shared buffer", [](auto, RTCGeometry t, auto, auto) {
    rtcSetSharedGeometryBuffer(t, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, memory + 1, 0, 12, 2);
  }));
  out.push_back(attempt("stride of 13 bytes", [](auto, RTCGeometry t, auto, auto) {
    rtcSetSharedGeometryBuffer(t, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, memory, 0, 13, 2);
  }));
  out.push_back(attempt("vertex buffer of an instance", [](auto, auto, RTCGeometry i, auto) {
    rtcSetNewGeometryBuffer(i, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, 3);
  }));
  out.push_back(attempt("buffer data of a slot beyond", [](auto, RTCGeometry t, auto, auto) {
    rtcGetGeometryBufferData(t, RTC_BUFFER_TYPE_VERTEX, 5);
  }));
  out.push_back(attempt("update of an unknown buffer type", [](auto, RTCGeometry t, auto, auto) {
    rtcUpdateGeometryBuffer(t, RTC_BUFFER_TYPE_NORMAL, 0);
  }));
  out.push_back(attempt("transform of a triangle mesh", [](auto, RTCGeometry t, auto, auto) {
    rtcSetGeometryTransform(t, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
  }));
  out.push_back(attempt("instanced scene of a triangle mesh", [](auto, RTCGeometry t, auto, RTCScene s) {
    rtcSetGeometryInstancedScene(t, s);
  }));
  out.push_back(attempt("transform at a time step beyond", [](auto, auto, RTCGeometry i, auto) {
    rtcSetGeometryTransform(i, 3, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
  }));
  out.push_back(attempt("transform as FLOAT4X4_ROW_MAJOR", [](auto, auto, RTCGeometry i, auto) {
    rtcSetGeometryTransform(i, 0, RTC_FORMAT_FLOAT4X4_ROW_MAJOR, identity);
  }));
  out.push_back(attempt("user primitive count of a mesh", [](auto, RTCGeometry t, auto, auto) {
    rtcSetGeometryUserPrimitiveCount(t, 3);
  }));
  out.push_back(attempt("tessellation rate of a mesh", [](auto, RTCGeometry t, auto, auto) {
    rtcSetGeometryTessellationRate(t, 3.0f);
  }));
  out.push_back(attempt("invalid geometry build quality", [](auto, RTCGeometry t, auto, auto) {
    rtcSetGeometryBuildQuality(t, RTCBuildQuality(9));
  }));
  out.push_back(attempt("time range ending before it starts", [](auto, RTCGeometry t, auto, auto) {
    rtcSetGeometryTimeRange(t, 0.5f, 0.2f);
  }));
  out.push_back(attempt("130 time steps", [](auto, RTCGeometry t, auto, auto) { rtcSetGeometryTimeStepCount(t, 130); }));
  out.push_back(attempt("unknown readable property", [](RTCDevice d, auto, auto, auto) {
    rtcGetDeviceProperty(d, RTCDeviceProperty(5));
  }));
  out.push_back(attempt("unknown writable property", [](RTCDevice d, auto, auto, auto) {
    rtcSetDeviceProperty(d, RTCDeviceProperty(5), 1);
  }));
  out.push_back(attempt("geometry id taken twice", [](auto, RTCGeometry t, auto, RTCScene s) {
    rtcAttachGeometryByID(s, t, 3);
    rtcAttachGeometryByID(s, t, 3);
  }));
  out.push_back(attempt("detach of a free id", [](auto, auto, auto, RTCScene s) { rtcDetachGeometry(s, 5); }));
  out.push_back(attempt("bounds of an uncommitted scene", [](auto, auto, auto, RTCScene s) {
    RTCBounds b;
    rtcGetSceneBounds(s, &b);
  }));
  out.push_back(attempt("release of a null geometry", [](auto, auto, auto, auto) { rtcReleaseGeometry(nullptr); }));
  out.push_back(attempt("mask of a null geometry", [](auto, auto, auto, auto) { rtcSetGeometryMask(nullptr, 1); }));
  out.push_back(attempt("a device with threads=abc", [](auto, auto, auto, auto) { rtcNewDevice("threads=abc"); }));
  out.push_back(attempt("the tokens Embree ignores", [](auto, auto, auto, auto) {
    rtcReleaseDevice(rtcNewDevice("threads=1,verbose=0,isa=avx2,set_affinity=1,foo=3,mbrt.kind=stbvh"));
  }));
  return out;
}
