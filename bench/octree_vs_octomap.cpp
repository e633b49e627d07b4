// rove OccupancyOctree vs OctoMap 1.9.7 in one run, on OctoMap's own test
// scan (../shared/datasets/octree/scan.dat.bz2, 88,206 points from the
// origin):
//   - insertion of the scan into an empty tree at 0.2, 0.1 and 0.05 m
//     (OctoMap's insertPointCloud with its defaults; rove's
//     insert_point_cloud, 1 and 2 threads), median wall time of --reps runs,
//     interleaved, and for one thread the median CPU time of the thread; nodes; the tree's memory (OctoMap's memoryUsage(), rove's
//     memory_usage()) and the peak RSS an insertion adds, each in a fresh
//     process of its own;
//   - point queries (search) at 2,000,000 random points and ray casts
//     (castRay / cast_ray, OctoMap arithmetic) on 200,000 random rays in the
//     0.1 m tree, per second.
// Usage: bench_octree_vs_octomap [--reps N] [--scan path/to/scan.dat.bz2]
#include <octomap/OcTree.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "rove/octree_reference_cases.h"
#include "rove/maps/occupancy_octree.h"
#include "rove/scan_dat.h"

namespace {

namespace ref = rove::octree_reference;
using Clock = std::chrono::steady_clock;

double seconds_of(const std::function<void()>& f) {
  const auto t0 = Clock::now();
  f();
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// CPU time of the calling process (all its threads), seconds.
double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// CPU time of the calling thread, seconds: on a shared machine it leaves
// out the time other processes held the core (not their effect on caches).
double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Wall time of f, and the calling thread's CPU time in `cpu`.
double seconds_of(const std::function<void()>& f, double& cpu) {
  const double c0 = thread_cpu_seconds();
  const double s = seconds_of(f);
  cpu = thread_cpu_seconds() - c0;
  return s;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// kB from a line of /proc/self/status ("VmRSS:", "VmHWM:").
long status_kb(const char* field) {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line)) {
    if (line.rfind(field, 0) == 0) return std::atol(line.c_str() + std::strlen(field));
  }
  return -1;
}

// Runs this program again as `--child <what> <res>` (a fresh process, so
// the allocator holds no memory freed earlier) and returns the peak RSS its
// insertion added, in MB, as the child prints it.
std::string g_self;
std::string g_scan;
double peak_rss_added_mb(const char* what, double res) {
  const std::string cmd = g_self + " --scan '" + g_scan + "' --child " + what + " " + std::to_string(res);
  FILE* p = popen(cmd.c_str(), "r");
  if (p == nullptr) return -1;
  double mb = -1;
  if (std::fscanf(p, "%lf", &mb) != 1) mb = -1;
  pclose(p);
  return mb;
}

octomap::Pointcloud to_octomap(const std::vector<Eigen::Vector3f>& pts) {
  octomap::Pointcloud c;
  for (const auto& p : pts) c.push_back(p.x(), p.y(), p.z());
  return c;
}

struct Row {
  double res;
  double octomap_ms, rove1_ms, rove2_ms, rove_octomap_arith_ms;
  double octomap_cpu_ms, rove1_cpu_ms;  // one thread: the calling thread's CPU time
  std::size_t octomap_nodes, rove_nodes;
  double octomap_mem_mb, rove_mem_mb, octomap_rss_mb, rove_rss_mb;
};

Row insertion(double res, const std::vector<Eigen::Vector3f>& pts, const octomap::Pointcloud& cloud, int reps) {
  Row r{};
  r.res = res;
  const octomap::point3d origin(0, 0, 0);
  const auto rove_run = [&](int threads, rove::OctreeRayArithmetic a) {
    rove::OccupancyOctree t(res);
    rove::OctreeInsertOptions o;
    o.num_threads = threads;
    o.arithmetic = a;
    t.insert_point_cloud(pts, Eigen::Vector3d::Zero(), o);
    return t;
  };
  std::vector<double> om, r1, r2, ra, om_cpu, r1_cpu;
  for (int i = 0; i < reps; ++i) {
    double cpu = 0.0;
    om.push_back(seconds_of(
        [&] {
          octomap::OcTree t(res);
          t.insertPointCloud(cloud, origin);
        },
        cpu));
    om_cpu.push_back(cpu);
    r1.push_back(seconds_of([&] { rove_run(1, rove::OctreeRayArithmetic::Double); }, cpu));
    r1_cpu.push_back(cpu);
    r2.push_back(seconds_of([&] { rove_run(2, rove::OctreeRayArithmetic::Double); }));
    ra.push_back(seconds_of([&] { rove_run(1, rove::OctreeRayArithmetic::OctoMap); }));
  }
  r.octomap_ms = 1e3 * median(om);
  r.rove1_ms = 1e3 * median(r1);
  r.rove2_ms = 1e3 * median(r2);
  r.rove_octomap_arith_ms = 1e3 * median(ra);
  r.octomap_cpu_ms = 1e3 * median(om_cpu);
  r.rove1_cpu_ms = 1e3 * median(r1_cpu);
  {
    octomap::OcTree t(res);
    t.insertPointCloud(cloud, origin);
    r.octomap_nodes = t.size();
    r.octomap_mem_mb = static_cast<double>(t.memoryUsage()) / 1048576.0;
  }
  {
    const rove::OccupancyOctree t = rove_run(1, rove::OctreeRayArithmetic::Double);
    r.rove_nodes = t.num_nodes();
    r.rove_mem_mb = static_cast<double>(t.memory_usage()) / 1048576.0;
  }
  r.octomap_rss_mb = peak_rss_added_mb("octomap", res);
  r.rove_rss_mb = peak_rss_added_mb("rove", res);
  return r;
}

void queries(const std::vector<Eigen::Vector3f>& pts, const octomap::Pointcloud& cloud, int reps) {
  const double res = 0.1;
  octomap::OcTree om(res);
  om.insertPointCloud(cloud, octomap::point3d(0, 0, 0));
  rove::OccupancyOctree rt(res);
  rove::OctreeInsertOptions opt;
  opt.arithmetic = rove::OctreeRayArithmetic::OctoMap;
  rt.insert_point_cloud(pts, Eigen::Vector3d::Zero(), opt);

  const ref::Box box{{-10.0f, -16.0f, -1.5f}, {28.0f, 17.0f, 10.5f}};
  constexpr std::size_t kPoints = 2000000, kRays = 200000;
  std::vector<float> q(3 * kPoints);
  ref::SplitMix64 g{42};
  for (std::size_t i = 0; i < kPoints; ++i) ref::random_point(g, box, &q[3 * i]);
  std::vector<ref::RayCase> rays;
  const ref::Box ray_box{{-2.0f, -2.0f, -0.5f}, {2.0f, 2.0f, 1.5f}};
  for (std::size_t i = 0; i < kRays; ++i) {
    ref::RayCase c = ref::random_ray(g, ray_box, i);
    c.max_range = 15.0;  // every ray bounded: the cost is the walk, not the edge of the map
    rays.push_back(c);
  }
  std::vector<double> tq_om, tq_rv, tr_om, tr_rv;
  std::size_t found_om = 0, found_rv = 0, hit_om = 0, hit_rv = 0;
  for (int rep = 0; rep < reps; ++rep) {
    found_om = found_rv = hit_om = hit_rv = 0;
    tq_om.push_back(seconds_of([&] {
      for (std::size_t i = 0; i < kPoints; ++i) found_om += om.search(q[3 * i], q[3 * i + 1], q[3 * i + 2]) != nullptr;
    }));
    tq_rv.push_back(seconds_of([&] {
      for (std::size_t i = 0; i < kPoints; ++i) {
        found_rv += rt.search(Eigen::Vector3d(q[3 * i], q[3 * i + 1], q[3 * i + 2])).has_value();
      }
    }));
    tr_om.push_back(seconds_of([&] {
      for (const auto& c : rays) {
        octomap::point3d end;
        hit_om += om.castRay(octomap::point3d(c.origin[0], c.origin[1], c.origin[2]),
                             octomap::point3d(c.direction[0], c.direction[1], c.direction[2]), end, c.ignore_unknown,
                             c.max_range);
      }
    }));
    tr_rv.push_back(seconds_of([&] {
      for (const auto& c : rays) {
        rove::OctreeRayCastOptions o;
        o.ignore_unknown = c.ignore_unknown;
        o.max_range = c.max_range;
        o.arithmetic = rove::OctreeRayArithmetic::OctoMap;
        hit_rv += rt.cast_ray(Eigen::Vector3d(c.origin[0], c.origin[1], c.origin[2]),
                              Eigen::Vector3d(c.direction[0], c.direction[1], c.direction[2]), o)
                      .hit();
      }
    }));
  }
  const double qom = kPoints / median(tq_om), qrv = kPoints / median(tq_rv);
  const double rom = kRays / median(tr_om), rrv = kRays / median(tr_rv);
  std::printf("\nqueries in the 0.1 m tree (median of %d)        OctoMap        rove   rove/OctoMap\n", reps);
  std::printf("point queries per second (%zu known)  %12.3g %12.3g %8.2fx%s\n", found_rv, qom, qrv, qrv / qom,
              found_om == found_rv ? "" : "  (DIFFERENT ANSWERS)");
  std::printf("ray casts per second (%zu hits)        %12.3g %12.3g %8.2fx%s\n", hit_rv, rom, rrv, rrv / rom,
              hit_om == hit_rv ? "" : "  (DIFFERENT ANSWERS)");
}

}  // namespace

int main(int argc, char** argv) {
  int reps = 5;
  std::string scan = ROVE_DATASETS_DIR "/octree/scan.dat.bz2";
  std::string child;
  double child_res = 0;
  int child_threads = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--reps") == 0) reps = std::max(1, std::atoi(argv[i + 1]));
    if (std::strcmp(argv[i], "--scan") == 0) scan = argv[i + 1];
    if (std::strcmp(argv[i], "--threads") == 0) child_threads = std::atoi(argv[i + 1]);
    if (std::strcmp(argv[i], "--child") == 0 && i + 2 < argc) {
      child = argv[i + 1];
      child_res = std::atof(argv[i + 2]);
      ++i;
    }
  }
  g_self = argv[0];
  g_scan = scan;
  std::vector<Eigen::Vector3f> pts;
  try {
    pts = rove::octree_test::read_scan_dat(scan);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_octree_vs_octomap: %s (the shared datasets are needed)\n", e.what());
    return 1;
  }
  const octomap::Pointcloud cloud = to_octomap(pts);
  if (!child.empty()) {
    // One insertion in this fresh process; prints the peak RSS it added (MB).
    { std::ofstream("/proc/self/clear_refs") << "5"; }  // reset VmHWM to the current RSS
    const long before = status_kb("VmRSS:");
    double seconds = 0;
    std::size_t nodes = 0;
    const double cpu0 = cpu_seconds();
    if (child == "octomap") {
      octomap::OcTree t(child_res);
      seconds = seconds_of([&] { t.insertPointCloud(cloud, octomap::point3d(0, 0, 0)); });
      nodes = t.size();
    } else {
      rove::OccupancyOctree t(child_res);
      rove::OctreeInsertOptions o;
      o.num_threads = child_threads;
      seconds = seconds_of([&] { t.insert_point_cloud(pts, Eigen::Vector3d::Zero(), o); });
      nodes = t.num_nodes();
    }
    std::printf("%.1f MB peak RSS added, %.1f ms, %.1f ms CPU, %zu nodes\n", (status_kb("VmHWM:") - before) / 1024.0,
                1e3 * seconds, 1e3 * (cpu_seconds() - cpu0), nodes);
    return 0;
  }
  std::printf("scan.dat: %zu points; median of %d runs, interleaved; load average at start: ", pts.size(), reps);
  std::ifstream la("/proc/loadavg");
  std::string load;
  std::getline(la, load);
  std::printf("%s\n\n", load.c_str());
  std::printf("insertion  OctoMap ms  rove ms (1 thr)  rove ms (2 thr)  rove ms (octomap arith.)  OctoMap/rove (1, 2 thr)"
              "  CPU ms OctoMap/rove (1 thr)  nodes OctoMap/rove  tree MB OctoMap/rove  peak RSS added MB OctoMap/rove\n");
  for (double res : {0.2, 0.1, 0.05}) {
    const Row r = insertion(res, pts, cloud, reps);
    std::printf("%.2f m %12.1f %16.1f %16.1f %25.1f %12.1fx %6.1fx %10.1f / %-7.1f %5.1fx %10zu / %-9zu %8.1f / %-8.1f "
                "%10.1f / %.1f\n",
                r.res, r.octomap_ms, r.rove1_ms, r.rove2_ms, r.rove_octomap_arith_ms, r.octomap_ms / r.rove1_ms,
                r.octomap_ms / r.rove2_ms, r.octomap_cpu_ms, r.rove1_cpu_ms, r.octomap_cpu_ms / r.rove1_cpu_ms,
                r.octomap_nodes, r.rove_nodes, r.octomap_mem_mb, r.rove_mem_mb, r.octomap_rss_mb, r.rove_rss_mb);
    std::fflush(stdout);
  }
  queries(pts, cloud, reps);
  return 0;
}
