// Part of embree_side.inl: sequences of calls whose observable results
// (hits, bounds, interpolated values, transforms, handles) must be the same
// on both builds of the API: commit and update (refit), shared and owned
// buffers, detach, disable, retain/release, user data, rtcInterpolate,
// rtcGetGeometryTransform, scene bounds.

RTCRayHit downRay(float x, float y, float time = 0.0f) {
  RTCRayHit rh{};
  rh.ray.org_x = x;
  rh.ray.org_y = y;
  rh.ray.org_z = -5;
  rh.ray.dir_z = 1;
  rh.ray.tfar = INFINITY;
  rh.ray.time = time;
  rh.ray.mask = ~0u;
  rh.hit.geomID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

// Hits of a grid of rays: geomID, primID and t of each.
void observeGrid(RTCScene s, std::vector<float>& out, float time = 0.0f) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < 12; ++j) {
      RTCRayHit rh = downRay(-1.07f + 0.2f * float(i), -1.03f + 0.2f * float(j), time);  // off the edges
      rtcIntersect1(s, &ctx, &rh);
      out.push_back(float(int(rh.hit.geomID)));
      out.push_back(float(int(rh.hit.primID)));
      out.push_back(rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? -1.0f : rh.ray.tfar);
    }
}

void observeBounds(RTCScene s, std::vector<float>& out) {
  RTCBounds b;
  rtcGetSceneBounds(s, &b);
  RTCLinearBounds l;
  rtcGetSceneLinearBounds(s, &l);
  for (const RTCBounds* x : {&b, &l.bounds0, &l.bounds1})
    out.insert(out.end(), {x->lower_x, x->lower_y, x->lower_z, x->upper_x, x->upper_y, x->upper_z});
}

std::vector<float> scenarios() {
  std::vector<float> out;
  RTCDevice d = rtcNewDevice(nullptr);
  RTCScene s = rtcNewScene(d);
  rtcSetSceneFlags(s, RTCSceneFlags(RTC_SCENE_FLAG_DYNAMIC | RTC_SCENE_FLAG_ROBUST));
  rtcSetSceneBuildQuality(s, RTC_BUILD_QUALITY_LOW);
  // A quad grid in z = 0 with shared vertices (stride 16, an offset), two steps.
  static float verts[2][4 + 4 * 25];
  static unsigned quads[16 * 4];
  for (int k = 0; k < 2; ++k)
    for (int v = 0; v < 25; ++v) {
      float* p = &verts[k][4 + 4 * v];
      p[0] = -1.0f + 0.5f * float(v % 5);
      p[1] = -1.0f + 0.5f * float(v / 5);
      p[2] = 0.1f * float(k) + 0.05f * float(v % 3);
    }
  for (int q = 0; q < 16; ++q) {
    const unsigned x = q % 4, y = q / 4, v0 = 5 * y + x;
    const unsigned idx[4] = {v0, v0 + 1, v0 + 6, v0 + 5};
    for (int c = 0; c < 4; ++c) quads[4 * q + c] = idx[c];
  }
  RTCGeometry grid = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_QUAD);
  rtcSetGeometryTimeStepCount(grid, 2);
  rtcSetSharedGeometryBuffer(grid, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, quads, 0, 16, 16);
  for (unsigned k = 0; k < 2; ++k)
    rtcSetSharedGeometryBuffer(grid, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, verts[k], 16, 16, 25);
  int userData = 7;
  rtcSetGeometryUserData(grid, &userData);
  rtcSetGeometryBuildQuality(grid, RTC_BUILD_QUALITY_REFIT);
  rtcCommitGeometry(grid);
  const unsigned gridID = rtcAttachGeometry(s, grid);
  // A triangle mesh with owned buffers and a vertex attribute.
  RTCGeometry tri = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryVertexAttributeCount(tri, 1);
  auto* tv = static_cast<float*>(rtcSetNewGeometryBuffer(tri, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, 3));
  const float tp[9] = {-0.4f, -0.4f, -1.0f, 0.6f, -0.3f, -1.0f, -0.2f, 0.7f, -0.8f};
  for (int i = 0; i < 9; ++i) tv[i] = tp[i];
  auto* ta = static_cast<float*>(rtcSetNewGeometryBuffer(tri, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, 0, RTC_FORMAT_FLOAT2, 8, 3));
  const float tc[6] = {0, 0, 1, 0, 0, 1};
  for (int i = 0; i < 6; ++i) ta[i] = tc[i];
  auto* ti = static_cast<unsigned*>(rtcSetNewGeometryBuffer(tri, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, 1));
  ti[0] = 0, ti[1] = 1, ti[2] = 2;
  rtcCommitGeometry(tri);
  rtcAttachGeometryByID(s, tri, 5);
  rtcCommitScene(s);
  observeGrid(s, out);
  observeGrid(s, out, 1.0f);
  observeBounds(s, out);

  // Handles and user data.
  out.push_back(rtcGetGeometry(s, gridID) == grid ? 1.0f : 0.0f);
  out.push_back(rtcGetGeometry(s, 5) == tri ? 1.0f : 0.0f);
  out.push_back(*static_cast<int*>(rtcGetGeometryUserData(rtcGetGeometry(s, gridID))));
  out.push_back(rtcGetGeometryBufferData(grid, RTC_BUFFER_TYPE_VERTEX, 1) == &verts[1][4] ? 1.0f : 0.0f);
  out.push_back(rtcGetGeometryBufferData(tri, RTC_BUFFER_TYPE_VERTEX, 0) == tv ? 1.0f : 0.0f);

  // rtcInterpolate: the triangle's attribute and the quads' positions.
  for (float uv : {0.1f, 0.3f, 0.45f}) {
    float P[3], du[3], dv[3];
    RTCInterpolateArguments a{tri, 0, uv, 0.5f * uv, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, 0, P, du, dv,
                              nullptr, nullptr, nullptr, 2};
    rtcInterpolate(&a);
    out.insert(out.end(), {P[0], P[1], du[0], du[1], dv[0], dv[1]});
    RTCInterpolateArguments q{grid, 5, uv, 1.5f * uv + 0.3f, RTC_BUFFER_TYPE_VERTEX, 1, P, du, dv,
                              nullptr, nullptr, nullptr, 3};
    rtcInterpolate(&q);
    out.insert(out.end(), {P[0], P[1], P[2], du[0], du[1], du[2], dv[0], dv[1], dv[2]});
  }

  // Vertex data changed in place: update, commit (a refit).
  for (int k = 0; k < 2; ++k)
    for (int v = 0; v < 25; ++v) verts[k][4 + 4 * v + 2] += 0.3f * float(v % 4);
  rtcUpdateGeometryBuffer(grid, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcUpdateGeometryBuffer(grid, RTC_BUFFER_TYPE_VERTEX, 1);
  rtcCommitGeometry(grid);
  rtcCommitScene(s);
  observeGrid(s, out, 0.5f);
  observeBounds(s, out);
  // A new vertex buffer of the same size for one step.
  static float moved[4 * 25];
  for (int v = 0; v < 25; ++v)
    for (int c = 0; c < 4; ++c) moved[4 * v + c] = verts[1][4 + 4 * v + c] + (c == 2 ? 0.5f : 0.0f);
  rtcSetSharedGeometryBuffer(grid, RTC_BUFFER_TYPE_VERTEX, 1, RTC_FORMAT_FLOAT3, moved, 0, 16, 25);
  rtcCommitGeometry(grid);
  rtcCommitScene(s);
  observeGrid(s, out, 0.75f);
  // Indices changed: a rebuild.
  std::swap(quads[4], quads[8]);
  rtcUpdateGeometryBuffer(grid, RTC_BUFFER_TYPE_INDEX, 0);
  rtcCommitGeometry(grid);
  rtcCommitScene(s);
  observeGrid(s, out, 0.25f);
  // Disabled, then detached and re-attached by id.
  rtcDisableGeometry(grid);
  rtcCommitScene(s);
  observeGrid(s, out);
  rtcEnableGeometry(grid);
  rtcRetainGeometry(tri);  // keeps it alive across the detach
  rtcDetachGeometry(s, 5);
  rtcCommitScene(s);
  observeGrid(s, out);
  rtcAttachGeometryByID(s, tri, 9);
  rtcReleaseGeometry(tri);
  rtcCommitScene(s);
  observeGrid(s, out);
  rtcReleaseGeometry(tri);
  rtcReleaseGeometry(grid);

  // Instances: transforms back and their bounds.
  RTCScene top = rtcNewScene(d);
  RTCGeometry a = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_INSTANCE), b = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(a, s);
  rtcSetGeometryInstancedScene(b, s);
  rtcSetGeometryTimeStepCount(a, 2);
  rtcSetGeometryTimeStepCount(b, 2);
  const float m0[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5f, 0, 0}, m1[12] = {0, 1, 0, -1, 0, 0, 0, 0, 1, 0.5f, 1, 0};
  rtcSetGeometryTransform(a, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m0);
  rtcSetGeometryTransform(a, 1, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m1);
  for (unsigned k = 0; k < 2; ++k) {
    RTCQuaternionDecomposition q;
    rtcInitQuaternionDecomposition(&q);
    rtcQuaternionDecompositionSetQuaternion(&q, std::cos(0.6f * float(k)), 0, 0, std::sin(0.6f * float(k)));
    rtcQuaternionDecompositionSetScale(&q, 0.5f, 0.5f, 1.0f);
    rtcQuaternionDecompositionSetTranslation(&q, -2.0f, 0, 0);
    rtcSetGeometryTransformQuaternion(b, k, &q);
  }
  for (RTCGeometry g : {a, b}) {
    rtcCommitGeometry(g);
    rtcAttachGeometry(top, g);
    rtcReleaseGeometry(g);
    for (float t : {0.0f, 0.3f, 1.0f}) {
      float x[16];
      rtcGetGeometryTransform(g, t, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, x);
      out.insert(out.end(), x, x + 16);
    }
  }
  rtcCommitScene(top);
  observeGrid(top, out, 0.4f);
  rtcRetainScene(top);
  rtcReleaseScene(top);
  rtcReleaseScene(top);
  rtcReleaseScene(s);
  rtcReleaseDevice(d);
  return out;
}
