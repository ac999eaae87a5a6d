#include "quantum/cloud.h"

namespace quantum {

void Cloud::reserve(size_t n, bool height) {
  x.reserve(n), y.reserve(n), vx.reserve(n), vy.reserve(n), w.reserve(n), tw.reserve(n), fate.reserve(n);
  if (height) z.reserve(n), vz.reserve(n);
}

void Cloud::clear() {
  x.clear(), y.clear(), vx.clear(), vy.clear(), w.clear(), tw.clear(), fate.clear(), z.clear(), vz.clear();
  mass = tmass = 0;
}

void Cloud::push(float px, float py, float pvx, float pvy, double pw, double ptw) {
  x.push_back(px), y.push_back(py), vx.push_back(pvx), vy.push_back(pvy);
  w.push_back(pw), tw.push_back(ptw), fate.push_back(kNoFate);
  mass += pw, tmass += ptw;
}

void Cloud::push(Vec3 p, Vec3 v, double pw, double ptw) {
  push(p.x, p.y, v.x, v.y, pw, ptw);
  z.push_back(p.z), vz.push_back(v.z);
}

void Cloud::push_from(const Cloud& o, size_t i) {
  push(o.x[i], o.y[i], o.vx[i], o.vy[i], o.w[i], o.tw[i]);
  fate.back() = o.fate[i];
  if (o.tall()) z.push_back(o.z[i]), vz.push_back(o.vz[i]);
}

void Cloud::remove_sorted(const std::vector<uint32_t>& indices) {
  size_t last = size();
  // Walk from the back so a particle moved into a hole is never one still to be removed.
  constexpr size_t kAhead = 8;  // holes are scattered over the cloud: fetch them early
  for (size_t k = indices.size(); k-- > 0;) {
    if (k >= kAhead) {
      const size_t h = indices[k - kAhead];
      for (const void* p : {(const void*)&x[h], (const void*)&y[h], (const void*)&vx[h], (const void*)&vy[h],
                            (const void*)&w[h], (const void*)&tw[h]})
        __builtin_prefetch(p, 1);
    }
    const size_t i = indices[k];
    mass -= w[i], tmass -= tw[i];
    --last;
    x[i] = x[last], y[i] = y[last], vx[i] = vx[last], vy[i] = vy[last], w[i] = w[last], tw[i] = tw[last];
    fate[i] = fate[last];
    if (tall()) z[i] = z[last], vz[i] = vz[last];
  }
  x.resize(last), y.resize(last), vx.resize(last), vy.resize(last), w.resize(last), tw.resize(last), fate.resize(last);
  if (tall()) z.resize(last), vz.resize(last);
  if (last == 0) mass = tmass = 0;
}

double Cloud::normalize() {
  double s = 0, ts = 0;
  for (size_t i = 0; i < size(); ++i) s += w[i], ts += tw[i];
  if (s <= 0) {
    mass = tmass = 0;
    return 0;
  }
  for (size_t i = 0; i < size(); ++i) w[i] /= s, tw[i] /= s;
  mass = 1, tmass = ts / s;
  return s;
}

void Cloud::reset_tweak() {
  tw = w;
  fate.assign(size(), kNoFate);
  tmass = mass;
}

}  // namespace quantum
