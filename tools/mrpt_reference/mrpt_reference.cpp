// Writes MRPT's results for the deterministic cases of
// modules/poses/tests/reference_cases.h into a little-endian binary file that
// modules/poses/tests/mrpt_reference_test.cpp reads. The format and the
// command that regenerates the file are in data/reference/README.md.
//
//   rove_mrpt_reference <output.bin> [--cases N]
//
// Every section regenerates its inputs from its own name (section_rng), so
// the test can rebuild them without the file storing them.

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/CQuaternion.h>
#include <mrpt/math/CVectorFixed.h>
#include <mrpt/poses/CPoint2D.h>
#include <mrpt/poses/CPoint3D.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPose3DQuat.h>
#include <mrpt/poses/CPose3DQuatPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/version.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "reference_cases.h"

namespace {

namespace ref = rove::reference;
using mrpt::math::CMatrixDouble33;
using mrpt::math::CMatrixDouble66;
using mrpt::math::CMatrixDouble77;
using mrpt::math::CQuaternionDouble;
using mrpt::poses::CPoint2D;
using mrpt::poses::CPoint3D;
using mrpt::poses::CPose2D;
using mrpt::poses::CPose3D;
using mrpt::poses::CPose3DPDFGaussian;
using mrpt::poses::CPose3DQuat;
using mrpt::poses::CPose3DQuatPDFGaussian;
using mrpt::poses::CPosePDFGaussian;

constexpr char kMagic[8] = {'R', 'O', 'V', 'E', 'R', 'E', 'F', '\n'};
constexpr std::uint32_t kFormatVersion = 1;

/// Output of one case, appended in order.
using Out = std::vector<double>;

struct Section {
  std::string name;
  std::uint32_t doubles_per_case = 0;
  std::uint64_t cases = 0;
  std::vector<double> values;
};

class Writer {
 public:
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<unsigned char>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<unsigned char>(v >> (8 * i)));
  }
  void f64(double d) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &d, sizeof bits);
    u64(bits);
  }
  void raw(const char* p, std::size_t n) { bytes_.insert(bytes_.end(), p, p + n); }
  void str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    raw(s.data(), s.size());
  }
  const std::vector<unsigned char>& bytes() const { return bytes_; }

 private:
  std::vector<unsigned char> bytes_;
};

CPose2D mrpt_pose2(const ref::Pose2In& p) { return CPose2D(p[0], p[1], p[2]); }
CPose3D mrpt_pose3(const ref::Pose3In& p) { return CPose3D(p[0], p[1], p[2], p[3], p[4], p[5]); }
CPose3DQuat mrpt_pose3quat(const ref::Pose3QuatIn& p) {
  return CPose3DQuat(p[0], p[1], p[2], CQuaternionDouble(p[3], p[4], p[5], p[6]));
}

template <std::size_t N, class M>
M mrpt_matrix(const ref::MatN<N>& a) {
  M m;
  for (std::size_t i = 0; i < N; ++i)
    for (std::size_t j = 0; j < N; ++j) m(i, j) = a[i * N + j];
  return m;
}

void put(Out& out, const CPose2D& p) { out.insert(out.end(), {p.x(), p.y(), p.phi()}); }
void put(Out& out, const CPoint2D& p) { out.insert(out.end(), {p.x(), p.y()}); }
void put(Out& out, const CPoint3D& p) { out.insert(out.end(), {p.x(), p.y(), p.z()}); }
void put(Out& out, const CPose3D& p) {
  out.insert(out.end(), {p.x(), p.y(), p.z(), p.yaw(), p.pitch(), p.roll()});
}
void put_quat(Out& out, const CQuaternionDouble& q) {
  out.insert(out.end(), {q.r(), q.x(), q.y(), q.z()});
}
void put(Out& out, const CPose3DQuat& p) {
  out.insert(out.end(), {p.x(), p.y(), p.z()});
  put_quat(out, p.quat());
}
template <class M>
void put_upper(Out& out, const M& m) {
  for (int i = 0; i < m.rows(); ++i)
    for (int j = i; j < m.cols(); ++j) out.push_back(m(i, j));
}

void add_section(std::vector<Section>& sections, const std::string& name,
                 std::uint32_t doubles_per_case, std::uint64_t cases,
                 const std::function<void(ref::SplitMix64&, std::size_t, Out&)>& compute) {
  Section s;
  s.name = name;
  s.doubles_per_case = doubles_per_case;
  s.cases = cases;
  s.values.reserve(cases * doubles_per_case);
  ref::SplitMix64 rng = ref::section_rng(name);
  Out out;
  for (std::size_t i = 0; i < cases; ++i) {
    out.clear();
    compute(rng, i, out);
    if (out.size() != doubles_per_case) {
      throw std::runtime_error("section " + name + ": case produced " +
                               std::to_string(out.size()) + " doubles, expected " +
                               std::to_string(doubles_per_case));
    }
    s.values.insert(s.values.end(), out.begin(), out.end());
  }
  sections.push_back(std::move(s));
}

std::vector<Section> compute_sections(std::uint64_t n) {
  std::vector<Section> s;

  // ---- 2D poses and points -------------------------------------------------
  add_section(s, "pose2_plus_pose2", 3, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose2(rng);
    const auto b = ref::pose2(rng);
    put(o, mrpt_pose2(a) + mrpt_pose2(b));
  });
  add_section(s, "pose2_minus_pose2", 3, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose2(rng);
    const auto b = ref::pose2(rng);
    put(o, mrpt_pose2(a) - mrpt_pose2(b));
  });
  add_section(s, "pose2_plus_point2", 2, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose2(rng);
    const auto p = ref::point2(rng);
    put(o, mrpt_pose2(a) + CPoint2D(p[0], p[1]));
  });
  add_section(s, "point2_minus_pose2", 2, n, [](auto& rng, std::size_t, Out& o) {
    const auto p = ref::point2(rng);
    const auto a = ref::pose2(rng);
    put(o, CPoint2D(p[0], p[1]) - mrpt_pose2(a));
  });

  // ---- 3D poses (yaw, pitch, roll) -----------------------------------------
  add_section(s, "pose3_plus_pose3", 6, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3(rng);
    const auto b = ref::pose3(rng);
    put(o, mrpt_pose3(a) + mrpt_pose3(b));
  });
  add_section(s, "pose3_minus_pose3", 6, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3(rng);
    const auto b = ref::pose3(rng);
    put(o, mrpt_pose3(a) - mrpt_pose3(b));
  });
  add_section(s, "pose3_plus_point3", 3, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3(rng);
    const auto p = ref::point3(rng);
    put(o, mrpt_pose3(a) + CPoint3D(p[0], p[1], p[2]));
  });
  add_section(s, "point3_minus_pose3", 3, n, [](auto& rng, std::size_t, Out& o) {
    const auto p = ref::point3(rng);
    const auto a = ref::pose3(rng);
    put(o, CPoint3D(p[0], p[1], p[2]) - mrpt_pose3(a));
  });
  add_section(s, "pose3_inverse", 6, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3(rng);
    put(o, -mrpt_pose3(a));
  });
  add_section(s, "pose2_plus_pose3", 6, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose2(rng);
    const auto b = ref::pose3(rng);
    put(o, mrpt_pose2(a) + mrpt_pose3(b));
  });
  add_section(s, "pose3_plus_pose2", 6, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3(rng);
    const auto b = ref::pose2(rng);
    put(o, mrpt_pose3(a) + CPose3D(mrpt_pose2(b)));
  });

  // ---- 3D poses (quaternion) -----------------------------------------------
  add_section(s, "pose3quat_plus_pose3quat", 7, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3quat(rng);
    const auto b = ref::pose3quat(rng);
    put(o, mrpt_pose3quat(a) + mrpt_pose3quat(b));
  });
  add_section(s, "pose3quat_minus_pose3quat", 7, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3quat(rng);
    const auto b = ref::pose3quat(rng);
    put(o, mrpt_pose3quat(a) - mrpt_pose3quat(b));
  });
  add_section(s, "pose3quat_plus_point3", 3, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3quat(rng);
    const auto p = ref::point3(rng);
    put(o, mrpt_pose3quat(a) + CPoint3D(p[0], p[1], p[2]));
  });
  add_section(s, "point3_minus_pose3quat", 3, n, [](auto& rng, std::size_t, Out& o) {
    const auto p = ref::point3(rng);
    const auto a = ref::pose3quat(rng);
    put(o, CPoint3D(p[0], p[1], p[2]) - mrpt_pose3quat(a));
  });

  // ---- Rotation conversions ------------------------------------------------
  // Translation is copied unchanged by both conversions: only the rotation is
  // stored.
  add_section(s, "pose3_to_pose3quat", 4, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3(rng);
    put_quat(o, CPose3DQuat(mrpt_pose3(a)).quat());
  });
  add_section(s, "pose3quat_to_pose3", 3, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3quat(rng);
    const CPose3D p(mrpt_pose3quat(a));
    o.insert(o.end(), {p.yaw(), p.pitch(), p.roll()});
  });
  add_section(s, "ypr_from_rotation", 3, n, [](auto& rng, std::size_t, Out& o) {
    const auto r = ref::rotation_from_quaternion(ref::quaternion(rng));
    const CPose3D p(mrpt_matrix<3, CMatrixDouble33>(r), mrpt::math::CVectorFixedDouble<3>());
    o.insert(o.end(), {p.yaw(), p.pitch(), p.roll()});
  });
  add_section(s, "ypr_from_rotation_gimbal", 3, n, [](auto& rng, std::size_t i, Out& o) {
    const auto r = ref::gimbal_rotation(rng, i);
    const CPose3D p(mrpt_matrix<3, CMatrixDouble33>(r), mrpt::math::CVectorFixedDouble<3>());
    o.insert(o.end(), {p.yaw(), p.pitch(), p.roll()});
  });

  // ---- Gaussian pose PDFs (covariances: upper triangles) -------------------
  add_section(s, "pose2_gaussian_plus", 6, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose2_gaussian(rng);
    const auto b = ref::pose2_gaussian(rng);
    CPosePDFGaussian pa(mrpt_pose2(a.mean), mrpt_matrix<3, CMatrixDouble33>(a.cov));
    const CPosePDFGaussian pb(mrpt_pose2(b.mean), mrpt_matrix<3, CMatrixDouble33>(b.cov));
    pa += pb;
    put_upper(o, pa.cov);
  });
  add_section(s, "pose2_gaussian_inverse", 6, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose2_gaussian(rng);
    const CPosePDFGaussian pa(mrpt_pose2(a.mean), mrpt_matrix<3, CMatrixDouble33>(a.cov));
    CPosePDFGaussian inv;
    pa.inverse(inv);
    put_upper(o, inv.cov);
  });
  add_section(s, "pose3_gaussian_plus", 21, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3_gaussian(rng);
    const auto b = ref::pose3_gaussian(rng);
    CPose3DPDFGaussian pa(mrpt_pose3(a.mean), mrpt_matrix<6, CMatrixDouble66>(a.cov));
    const CPose3DPDFGaussian pb(mrpt_pose3(b.mean), mrpt_matrix<6, CMatrixDouble66>(b.cov));
    pa += pb;
    put_upper(o, pa.cov);
  });
  add_section(s, "pose3_gaussian_inverse", 21, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3_gaussian(rng);
    const CPose3DPDFGaussian pa(mrpt_pose3(a.mean), mrpt_matrix<6, CMatrixDouble66>(a.cov));
    CPose3DPDFGaussian inv;
    pa.inverse(inv);
    put_upper(o, inv.cov);
  });
  // Quaternion PDFs store the mean's quaternion too: the test needs MRPT's
  // sign to align the quaternion rows of the covariance.
  add_section(s, "pose3quat_gaussian_plus", 4 + 28, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3quat_gaussian(rng);
    const auto b = ref::pose3quat_gaussian(rng);
    CPose3DQuatPDFGaussian pa(mrpt_pose3quat(a.mean), mrpt_matrix<7, CMatrixDouble77>(a.cov));
    const CPose3DQuatPDFGaussian pb(mrpt_pose3quat(b.mean),
                                    mrpt_matrix<7, CMatrixDouble77>(b.cov));
    pa += pb;
    put_quat(o, pa.mean.quat());
    put_upper(o, pa.cov);
  });
  add_section(s, "pose3quat_gaussian_inverse", 4 + 28, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3quat_gaussian(rng);
    const CPose3DQuatPDFGaussian pa(mrpt_pose3quat(a.mean),
                                    mrpt_matrix<7, CMatrixDouble77>(a.cov));
    CPose3DQuatPDFGaussian inv;
    pa.inverse(inv);
    put_quat(o, inv.mean.quat());
    put_upper(o, inv.cov);
  });
  add_section(s, "pose3_gaussian_to_quat", 4 + 28, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3_gaussian(rng);
    const CPose3DPDFGaussian pa(mrpt_pose3(a.mean), mrpt_matrix<6, CMatrixDouble66>(a.cov));
    const CPose3DQuatPDFGaussian q(pa);
    put_quat(o, q.mean.quat());
    put_upper(o, q.cov);
  });
  add_section(s, "pose3quat_gaussian_to_euler", 21, n, [](auto& rng, std::size_t, Out& o) {
    const auto a = ref::pose3quat_gaussian(rng);
    const CPose3DQuatPDFGaussian pa(mrpt_pose3quat(a.mean),
                                    mrpt_matrix<7, CMatrixDouble77>(a.cov));
    const CPose3DPDFGaussian e(pa);
    put_upper(o, e.cov);
  });
  return s;
}

/// "MRPT 2.5.8" from the packed MRPT_VERSION (0x258).
std::string fmt_mrpt_version() {
  return "MRPT " + std::to_string((MRPT_VERSION >> 8) & 0xF) + "." +
         std::to_string((MRPT_VERSION >> 4) & 0xF) + "." + std::to_string(MRPT_VERSION & 0xF);
}

int usage() {
  std::cerr << "usage: rove_mrpt_reference <output.bin> [--cases N]\n"
               "Writes MRPT's results for modules/poses/tests/reference_cases.h.\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  std::string output;
  std::uint64_t cases = 1000;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--cases" && i + 1 < argc) {
      cases = std::strtoull(argv[++i], nullptr, 10);
      if (cases == 0) return usage();
    } else if (!arg.empty() && arg[0] == '-') {
      return usage();
    } else {
      output = arg;
    }
  }
  if (output.empty()) return usage();

  try {
    const std::vector<Section> sections = compute_sections(cases);
    Writer w;
    w.raw(kMagic, sizeof kMagic);
    w.u32(kFormatVersion);
    w.u32(ref::kInputsVersion);
    w.str(fmt_mrpt_version());
    w.u32(static_cast<std::uint32_t>(sections.size()));
    for (const Section& s : sections) {
      w.str(s.name);
      w.u64(s.cases);
      w.u32(s.doubles_per_case);
      for (const double d : s.values) w.f64(d);
    }
    std::ofstream f(output, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(w.bytes().data()),
            static_cast<std::streamsize>(w.bytes().size()));
    f.close();
    if (!f) {
      std::cerr << "rove_mrpt_reference: cannot write " << output << '\n';
      return 1;
    }
    std::cout << "wrote " << output << ": " << sections.size() << " sections, " << cases
              << " cases each, " << w.bytes().size() << " bytes\n";
  } catch (const std::exception& e) {
    std::cerr << "rove_mrpt_reference: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
