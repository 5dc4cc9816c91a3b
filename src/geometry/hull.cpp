// Convex hulls (hull.hpp): Bullet's btConvexHullComputer, its faces re-formed from the given
// coordinates. Besides collision/bullet_adapter.cpp, the only file that includes Bullet.
#include "geometry/hull.hpp"

#include <LinearMath/btConvexHullComputer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

namespace rbpart {

static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 arrays are passed to Bullet as packed doubles");

HullFaces convex_hull_faces(const std::vector<Vec3>& points) {
  HullFaces out;
  const int n = static_cast<int>(points.size());
  if (n == 0) return out;
  btConvexHullComputer hull;
  hull.compute(points.front().data(), static_cast<int>(sizeof(Vec3)), n, 0, 0);

  Vec3 lo = points[0], hi = points[0];
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // Planar to round-off: far below Bullet's rounding grid (1e-4 of the extent).
  const double tolerance = 1e-10 * (hi - lo).maxCoeff();

  // Bullet's faces, fanned into triangles over the input indices, with unit normals.
  std::vector<std::array<int, 3>> tris;
  for (int f = 0; f < hull.faces.size(); ++f) {
    const btConvexHullComputer::Edge* first = &hull.edges[hull.faces[f]];
    const int v0 = hull.original_vertex_index[first->getSourceVertex()];
    for (const btConvexHullComputer::Edge* e = first->getNextEdgeOfFace(); e->getTargetVertex() != first->getSourceVertex();
         e = e->getNextEdgeOfFace())
      tris.push_back({v0, hull.original_vertex_index[e->getSourceVertex()], hull.original_vertex_index[e->getTargetVertex()]});
  }
  const int t = static_cast<int>(tris.size());
  std::vector<Vec3> normal(t);
  for (int i = 0; i < t; ++i) {
    const Vec3& a = points[tris[i][0]];
    const Vec3 c = (points[tris[i][1]] - a).cross(points[tris[i][2]] - a);
    normal[i] = c.norm() > 0 ? Vec3(c.normalized()) : Vec3::Zero();
  }

  // Adjacent triangles coplanar in the input coordinates form one face (union-find): Bullet
  // decides on rounded points, which splits the planar faces of a rotated box, for one.
  struct HalfEdge {
    int from, to, tri;
    bool operator<(const HalfEdge& o) const { return from != o.from ? from < o.from : to < o.to; }
  };
  std::vector<HalfEdge> edges;
  for (int i = 0; i < t; ++i)
    for (int k = 0; k < 3; ++k) edges.push_back({tris[i][k], tris[i][(k + 1) % 3], i});
  std::sort(edges.begin(), edges.end());
  const int m = static_cast<int>(edges.size());
  std::vector<int> twin(m, -1);  // the triangle across each half-edge
  for (int i = 0; i < m; ++i) {
    const auto it = std::lower_bound(edges.begin(), edges.end(), HalfEdge{edges[i].to, edges[i].from, -1});
    if (it != edges.end() && it->from == edges[i].to && it->to == edges[i].from) twin[i] = it->tri;
  }
  auto on_plane = [&](int plane, int tri) {
    for (int v : tris[tri])
      if (std::abs(normal[plane].dot(points[v] - points[tris[plane][0]])) > tolerance) return false;
    return true;
  };
  std::vector<int> group(t);
  for (int i = 0; i < t; ++i) group[i] = i;
  const std::function<int(int)> root = [&](int i) { return group[i] == i ? i : group[i] = root(group[i]); };
  for (int i = 0; i < m; ++i) {
    const int a = edges[i].tri, b = twin[i];
    if (b < 0 || root(a) == root(b)) continue;
    // A zero-area triangle (a vertex on an edge: the fan of a Bullet face through it) has a zero
    // normal and lies "on" both faces along that edge; it joins neither (> 0), or it would chain
    // them into one group, left as triangles beside a face of zero normal.
    if (normal[a].dot(normal[b]) > 0 && on_plane(a, b) && on_plane(b, a)) group[root(a)] = root(b);
  }

  // Each face's boundary: the half-edges whose twin lies in another face, walked in the triangles'
  // (counter-clockwise) direction; vertices in line with their neighbours are dropped. A boundary
  // that is not one simple loop (impossible on a convex hull) leaves the face as its triangles.
  std::vector<int> boundary;  // half-edges on face boundaries, grouped by face
  for (int i = 0; i < m; ++i)
    if (twin[i] < 0 || root(twin[i]) != root(edges[i].tri)) boundary.push_back(i);
  std::stable_sort(boundary.begin(), boundary.end(),
                   [&](int x, int y) { return root(edges[x].tri) < root(edges[y].tri); });
  std::vector<int> next(n, -1), loop, face;
  auto emit = [&](const std::vector<int>& vertices) {
    out.indices.insert(out.indices.end(), vertices.begin(), vertices.end());
    out.offsets.push_back(static_cast<int>(out.indices.size()));
  };
  out.offsets.push_back(0);
  for (std::size_t begin = 0, end; begin < boundary.size(); begin = end) {
    const int g = root(edges[boundary[begin]].tri);
    for (end = begin; end < boundary.size() && root(edges[boundary[end]].tri) == g; ++end)
      next[edges[boundary[end]].from] = edges[boundary[end]].to;
    const int size = static_cast<int>(end - begin), start = edges[boundary[begin]].from;
    loop.clear();
    int v = start;
    do {
      loop.push_back(v);
      v = next[v];
    } while (v >= 0 && v != start && static_cast<int>(loop.size()) <= size);
    for (std::size_t j = begin; j < end; ++j) next[edges[boundary[j]].from] = -1;
    if (v != start || static_cast<int>(loop.size()) != size) {
      for (int i = 0; i < t; ++i)
        if (root(i) == g) emit({tris[i].begin(), tris[i].end()});
      continue;
    }
    face.clear();
    const int k = static_cast<int>(loop.size());
    for (int j = 0; j < k; ++j) {
      const Vec3& prev = points[loop[(j + k - 1) % k]];
      const Vec3& here = points[loop[j]];
      const Vec3& after = points[loop[(j + 1) % k]];
      if ((here - prev).cross(after - here).norm() > tolerance * (after - prev).norm()) face.push_back(loop[j]);
    }
    if (face.size() >= 3) emit(face);  // else a sliver of zero area
  }
  if (out.offsets.size() == 1) out.offsets.clear();
  return out;
}

}  // namespace rbpart
