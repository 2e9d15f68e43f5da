#include "integrators/photon_map/photon_map.h"
#include <chrono>
#include <cmath>
#include <cstdint>

namespace lb {

PointIndex::PointIndex(const std::vector<Vec3>& points) : count_(points.size()) {
  if (points.empty()) return;
  coords_.resize(points.size() * 3);
  for (size_t i = 0; i < points.size(); ++i)
    coords_[3 * i] = points[i].x, coords_[3 * i + 1] = points[i].y, coords_[3 * i + 2] = points[i].z;
  flann::Matrix<float> data(coords_.data(), points.size(), 3);
  index_ = std::make_unique<flann::Index<flann::L2_Simple<float>>>(data, flann::KDTreeSingleIndexParams(10));
  index_->buildIndex();
}

void PointIndex::knn(const Vec3& q, size_t k, float maxRadius, std::vector<std::pair<size_t, float>>& out) const {
  out.clear();
  if (!index_ || k == 0 || !(maxRadius > 0)) return;
  float query[3] = {q.x, q.y, q.z};
  flann::Matrix<float> qm(query, 1, 3);
  if (!std::isfinite(maxRadius)) {
    k = std::min(k, count_);
    thread_local std::vector<size_t> idx;  // reused: a query allocates nothing
    thread_local std::vector<float> dist;
    idx.resize(k), dist.resize(k);
    flann::Matrix<size_t> im(idx.data(), 1, k);
    flann::Matrix<float> dm(dist.data(), 1, k);
    flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED, 0, true);  // exact, sorted
    int found = index_->knnSearch(qm, im, dm, k, params);
    for (int i = 0; i < found; ++i) out.push_back({idx[size_t(i)], dist[size_t(i)]});
    return;
  }
  // Bounded by maxRadius: FLANN's radius search keeping the k nearest (a
  // heap of k), so the search never visits the tree beyond the disc and k
  // may be as large as the map ("every photon in the disc").
  thread_local std::vector<std::vector<size_t>> idx;
  thread_local std::vector<std::vector<float>> dist;
  flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED, 0, true);  // exact, sorted
  params.max_neighbors = k >= count_ ? -1 : int(std::min<size_t>(k, size_t(INT32_MAX)));
  index_->radiusSearch(qm, idx, dist, maxRadius * maxRadius, params);  // FLANN takes the squared radius
  for (size_t i = 0; i < idx[0].size(); ++i) out.push_back({idx[0][i], dist[0][i]});
}

void PointIndex::radius(const Vec3& q, float radius, std::vector<std::pair<size_t, float>>& out) const {
  out.clear();
  if (!index_ || !(radius > 0)) return;
  float query[3] = {q.x, q.y, q.z};
  flann::Matrix<float> qm(query, 1, 3);
  // Reused per thread: SPPM calls this once per photon (FLANN resizes each row to the result).
  thread_local std::vector<std::vector<size_t>> idx;
  thread_local std::vector<std::vector<float>> dist;
  flann::SearchParams params(flann::FLANN_CHECKS_UNLIMITED, 0, false);
  index_->radiusSearch(qm, idx, dist, radius * radius, params);  // FLANN takes the squared radius
  for (size_t i = 0; i < idx[0].size(); ++i) out.push_back({idx[0][i], dist[0][i]});
}

PhotonMap::PhotonMap(std::vector<Photon> photons) : photons_(std::move(photons)) {
  auto start = std::chrono::steady_clock::now();
  std::vector<Vec3> points;
  points.reserve(photons_.size());
  for (const auto& ph : photons_) points.push_back(ph.p);
  index_ = std::make_unique<PointIndex>(points);
  buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace lb
