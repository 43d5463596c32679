// Part of embree_side.inl: the rays traced in each packet and stream form.

void toLane(const TestRay& r, RTCRayN* ray, unsigned N, unsigned i) {
  RTCRayN_org_x(ray, N, i) = r.org.x;
  RTCRayN_org_y(ray, N, i) = r.org.y;
  RTCRayN_org_z(ray, N, i) = r.org.z;
  RTCRayN_tnear(ray, N, i) = r.tnear;
  RTCRayN_dir_x(ray, N, i) = r.dir.x;
  RTCRayN_dir_y(ray, N, i) = r.dir.y;
  RTCRayN_dir_z(ray, N, i) = r.dir.z;
  RTCRayN_time(ray, N, i) = r.time;
  RTCRayN_tfar(ray, N, i) = r.tfar;
  RTCRayN_mask(ray, N, i) = r.mask;
  RTCRayN_id(ray, N, i) = i;
  RTCRayN_flags(ray, N, i) = 0;
}

void clearHit(RTCHitN* hit, unsigned N, unsigned i) {
  RTCHitN_geomID(hit, N, i) = RTC_INVALID_GEOMETRY_ID;
  RTCHitN_primID(hit, N, i) = RTC_INVALID_GEOMETRY_ID;
  RTCHitN_instID(hit, N, i, 0) = RTC_INVALID_GEOMETRY_ID;
}

void fromLane(RTCRayN* ray, RTCHitN* hit, unsigned N, unsigned i, TestAnswer& a) {
  a.geomID = RTCHitN_geomID(hit, N, i);
  a.hit = a.geomID != RTC_INVALID_GEOMETRY_ID;
  if (!a.hit) return;
  a.t = RTCRayN_tfar(ray, N, i);
  a.u = RTCHitN_u(hit, N, i);
  a.v = RTCHitN_v(hit, N, i);
  a.Ng = {RTCHitN_Ng_x(hit, N, i), RTCHitN_Ng_y(hit, N, i), RTCHitN_Ng_z(hit, N, i)};
  a.primID = RTCHitN_primID(hit, N, i);
  a.instID = RTCHitN_instID(hit, N, i, 0);
}

template <unsigned N, class RayHitT, class RayT, class Intersect, class Occluded>
void tracePackets(RTCScene scene, RTCIntersectContext* ctx, const std::vector<TestRay>& rays,
                  std::vector<TestAnswer>& out, Intersect intersect, Occluded occluded) {
  for (size_t base = 0; base < rays.size(); base += N) {
    alignas(64) RayHitT rh;
    alignas(64) RayT r;
    alignas(64) int valid[N];
    auto* rayN = RTCRayHitN_RayN(reinterpret_cast<RTCRayHitN*>(&rh), N);
    auto* hitN = RTCRayHitN_HitN(reinterpret_cast<RTCRayHitN*>(&rh), N);
    for (unsigned i = 0; i < N; ++i) {
      valid[i] = base + i < rays.size() ? -1 : 0;
      const TestRay& src = rays[valid[i] ? base + i : base];
      toLane(src, rayN, N, i);
      clearHit(hitN, N, i);
      toLane(src, reinterpret_cast<RTCRayN*>(&r), N, i);
    }
    intersect(valid, scene, ctx, &rh);
    occluded(valid, scene, ctx, &r);
    for (unsigned i = 0; i < N && base + i < rays.size(); ++i) {
      fromLane(rayN, hitN, N, i, out[base + i]);
      out[base + i].occluded = RTCRayN_tfar(reinterpret_cast<RTCRayN*>(&r), N, i) < 0.0f;
    }
  }
}

void traceWith(const Built& b, const std::vector<TestRay>& rays, std::vector<TestAnswer>& out, TraceMode mode,
               RTCFilterFunctionN ctxFilter) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.filter = ctxFilter;
  out.assign(rays.size(), TestAnswer{});
  const size_t n = rays.size();
  std::vector<RTCRayHit> rh(n);
  std::vector<RTCRay> r(n);
  for (size_t i = 0; i < n; ++i) {
    toLane(rays[i], reinterpret_cast<RTCRayN*>(&rh[i].ray), 1, 0);
    clearHit(reinterpret_cast<RTCHitN*>(&rh[i].hit), 1, 0);
    toLane(rays[i], reinterpret_cast<RTCRayN*>(&r[i]), 1, 0);
  }
  switch (mode) {
    case TraceMode::Single:
      for (size_t i = 0; i < n; ++i) {
        rtcIntersect1(b.top, &ctx, &rh[i]);
        rtcOccluded1(b.top, &ctx, &r[i]);
      }
      break;
    case TraceMode::Packet4:
      return tracePackets<4, RTCRayHit4, RTCRay4>(b.top, &ctx, rays, out, rtcIntersect4, rtcOccluded4);
    case TraceMode::Packet8:
      return tracePackets<8, RTCRayHit8, RTCRay8>(b.top, &ctx, rays, out, rtcIntersect8, rtcOccluded8);
    case TraceMode::Packet16:
      return tracePackets<16, RTCRayHit16, RTCRay16>(b.top, &ctx, rays, out, rtcIntersect16, rtcOccluded16);
    case TraceMode::Stream1M:
      rtcIntersect1M(b.top, &ctx, rh.data(), unsigned(n), sizeof(RTCRayHit));
      rtcOccluded1M(b.top, &ctx, r.data(), unsigned(n), sizeof(RTCRay));
      break;
    case TraceMode::Stream1Mp: {
      std::vector<RTCRayHit*> ph(n);
      std::vector<RTCRay*> pr(n);
      for (size_t i = 0; i < n; ++i) {
        ph[i] = &rh[i];
        pr[i] = &r[i];
      }
      rtcIntersect1Mp(b.top, &ctx, ph.data(), unsigned(n));
      rtcOccluded1Mp(b.top, &ctx, pr.data(), unsigned(n));
      break;
    }
    case TraceMode::StreamNM: {
      // Packets of 8, the lanes past the end inactive (tnear > tfar).
      const size_t m = (n + 7) / 8;
      std::vector<RTCRayHit8> packets(m);
      std::vector<RTCRay8> shadow(m);
      for (size_t i = 0; i < m * 8; ++i) {
        TestRay t = i < n ? rays[i] : TestRay{};
        if (i >= n) t.tnear = 1.0f, t.tfar = 0.0f;
        auto* p = reinterpret_cast<RTCRayHitN*>(&packets[i / 8]);
        toLane(t, RTCRayHitN_RayN(p, 8), 8, i % 8);
        clearHit(RTCRayHitN_HitN(p, 8), 8, i % 8);
        toLane(t, reinterpret_cast<RTCRayN*>(&shadow[i / 8]), 8, i % 8);
      }
      rtcIntersectNM(b.top, &ctx, reinterpret_cast<RTCRayHitN*>(packets.data()), 8, unsigned(m), sizeof(RTCRayHit8));
      rtcOccludedNM(b.top, &ctx, reinterpret_cast<RTCRayN*>(shadow.data()), 8, unsigned(m), sizeof(RTCRay8));
      for (size_t i = 0; i < n; ++i) {
        auto* p = reinterpret_cast<RTCRayHitN*>(&packets[i / 8]);
        fromLane(RTCRayHitN_RayN(p, 8), RTCRayHitN_HitN(p, 8), 8, i % 8, out[i]);
        out[i].occluded = RTCRayN_tfar(reinterpret_cast<RTCRayN*>(&shadow[i / 8]), 8, i % 8) < 0.0f;
      }
      return;
    }
    case TraceMode::StreamNp: {
      // Pointer SOA: one array per component.
      std::vector<float> f[17];
      std::vector<unsigned> u[7];
      for (auto& a : f) a.resize(n);
      for (auto& a : u) a.resize(n);
      RTCRayHitNp p;
      float** fp[] = {&p.ray.org_x, &p.ray.org_y, &p.ray.org_z, &p.ray.tnear, &p.ray.dir_x, &p.ray.dir_y,
                      &p.ray.dir_z, &p.ray.time,  &p.ray.tfar,  &p.hit.Ng_x,  &p.hit.Ng_y,  &p.hit.Ng_z,
                      &p.hit.u,     &p.hit.v};
      unsigned** up[] = {&p.ray.mask, &p.ray.id, &p.ray.flags, &p.hit.primID, &p.hit.geomID, &p.hit.instID[0]};
      for (int k = 0; k < 14; ++k) *fp[k] = f[k].data();
      for (int k = 0; k < 6; ++k) *up[k] = u[k].data();
      for (size_t i = 0; i < n; ++i) {
        const RTCRay& s = rh[i].ray;
        f[0][i] = s.org_x, f[1][i] = s.org_y, f[2][i] = s.org_z, f[3][i] = s.tnear, f[4][i] = s.dir_x;
        f[5][i] = s.dir_y, f[6][i] = s.dir_z, f[7][i] = s.time, f[8][i] = s.tfar;
        u[0][i] = s.mask, u[1][i] = s.id, u[2][i] = s.flags;
        u[3][i] = u[4][i] = u[5][i] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersectNp(b.top, &ctx, &p, unsigned(n));
      for (size_t i = 0; i < n; ++i) {
        TestAnswer& a = out[i];
        a.geomID = u[4][i];
        a.hit = a.geomID != RTC_INVALID_GEOMETRY_ID;
        if (a.hit) a = {true, f[8][i], f[12][i], f[13][i], {f[9][i], f[10][i], f[11][i]}, u[4][i], u[3][i], u[5][i]};
      }
      for (size_t i = 0; i < n; ++i) f[8][i] = rh[i].ray.tfar;  // the shadow rays start as the others did
      rtcOccludedNp(b.top, &ctx, &p.ray, unsigned(n));
      for (size_t i = 0; i < n; ++i) out[i].occluded = f[8][i] < 0.0f;
      return;
    }
  }
  for (size_t i = 0; i < n; ++i) {
    fromLane(reinterpret_cast<RTCRayN*>(&rh[i].ray), reinterpret_cast<RTCHitN*>(&rh[i].hit), 1, 0, out[i]);
    out[i].occluded = r[i].tfar < 0.0f;
  }
}
