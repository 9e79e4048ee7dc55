// Lesson 3: close the loop in a pose graph with memloop's loop closures (Ceres).
//
// A SLAM back-end keeps a graph: a vertex per image at its estimated pose, odometry edges between
// consecutive images, and memloop's loop-closure edges between an image and the one it revisits.
// Odometry drifts; the loop closures pull the trajectory back. This reads the graph that
// `memloop export MAP.db --format g2o --poses ODOMETRY.txt` writes, optimizes it with Ceres
// (the costs of Ceres' own pose_graph_3d example, in g2o's error convention), a robust loss on
// the loop closures so that a wrong one cannot bend the map, and writes the optimized trajectory.
//
// Usage: 03_pose_graph [--no-robust-loss] GRAPH.g2o MAP.db OPTIMIZED.txt [TRUTH.txt]
//   MAP.db gives each vertex (image index) its time stamp; OPTIMIZED.txt is a TUM trajectory
//   (time tx ty tz qx qy qz qw). With TRUTH.txt (a TUM trajectory of the same images), prints the
//   absolute trajectory error (ATE: RMSE of positions after the best rigid alignment) and the
//   RMSE of the rotations, before and after. --no-robust-loss leaves the loop closures' costs
//   quadratic (to see what the loss does).
#include <ceres/ceres.h>
#include <memloop/map_info.h>  // ReadMapImages: the images' time stamps

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

struct Pose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

struct Edge {
  int from = 0, to = 0;
  Pose measured;  // `to` in `from`'s frame
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  bool loop_closure = false;  // not between consecutive vertices
};

struct Graph {
  std::map<int, Pose> vertices;
  std::vector<Edge> edges;
  std::vector<int> fixed;
};

[[noreturn]] void Fail(const std::string& message) {
  std::cerr << "03_pose_graph: " << message << "\n";
  std::exit(1);
}

// g2o's text format: VERTEX_SE3:QUAT id x y z qx qy qz qw; EDGE_SE3:QUAT from to x y z qx qy qz qw
// and the information matrix's upper triangle (21 values, row by row); FIX id.
Graph ReadG2o(const std::string& path) {
  std::ifstream in(path);
  if (!in) Fail(path + ": cannot be read");
  Graph graph;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream fields(line);
    std::string tag;
    if (!(fields >> tag) || tag[0] == '#') continue;
    const auto read_pose = [&](Pose& pose) {
      double x, y, z, qx, qy, qz, qw;
      if (!(fields >> x >> y >> z >> qx >> qy >> qz >> qw)) return false;
      pose = {{x, y, z}, Eigen::Quaterniond(qw, qx, qy, qz).normalized()};
      return true;
    };
    bool read = false;
    if (tag == "VERTEX_SE3:QUAT") {
      int id;
      Pose pose;
      read = (fields >> id) && read_pose(pose);
      if (read) graph.vertices[id] = pose;
    } else if (tag == "EDGE_SE3:QUAT") {
      Edge edge;
      read = (fields >> edge.from >> edge.to) && read_pose(edge.measured);
      for (int row = 0; row < 6 && read; ++row) {
        for (int column = row; column < 6 && read; ++column) {
          read = static_cast<bool>(fields >> edge.information(row, column));
          edge.information(column, row) = edge.information(row, column);
        }
      }
      graph.edges.push_back(edge);
    } else if (tag == "FIX") {
      int id;
      read = static_cast<bool>(fields >> id);
      graph.fixed.push_back(id);
    }
    if (!read) Fail(path + ": line " + std::to_string(number) + ": not a g2o record this reads");
  }
  if (graph.vertices.empty()) {
    Fail(path + ": no VERTEX_SE3:QUAT (export with --poses ODOMETRY to have them)");
  }
  // Odometry joins each vertex to the next one; any other edge is a loop closure.
  std::map<int, int> next;
  for (auto it = graph.vertices.begin(); std::next(it) != graph.vertices.end(); ++it) {
    next[it->first] = std::next(it)->first;
  }
  for (Edge& edge : graph.edges) {
    if (!graph.vertices.count(edge.from) || !graph.vertices.count(edge.to)) {
      Fail(path + ": an edge " + std::to_string(edge.from) + " -> " + std::to_string(edge.to) +
           " names a vertex the file does not have");
    }
    edge.loop_closure = next.count(edge.from) == 0 || next[edge.from] != edge.to;
  }
  return graph;
}

// g2o's EdgeSE3 error: the measurement's inverse times the estimate of `to` in `from`'s frame, as
// its translation and the vector part of its quaternion (about half the angle), weighted by the
// square root of the information.
class RelativePoseError {
 public:
  RelativePoseError(const Pose& measured, const Eigen::Matrix<double, 6, 6>& information)
      : measured_(measured), sqrt_information_(information.llt().matrixL().transpose()) {}

  template <typename T>
  bool operator()(const T* position_a, const T* rotation_a, const T* position_b,
                  const T* rotation_b, T* residuals) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_a(position_a), p_b(position_b);
    const Eigen::Map<const Eigen::Quaternion<T>> q_a(rotation_a), q_b(rotation_b);
    const Eigen::Quaternion<T> q_ab = q_a.conjugate() * q_b;
    const Eigen::Matrix<T, 3, 1> p_ab = q_a.conjugate() * (p_b - p_a);
    const Eigen::Quaternion<T> q_measured = measured_.rotation.template cast<T>();
    Eigen::Quaternion<T> delta = q_measured.conjugate() * q_ab;
    if (delta.w() < T(0)) delta.coeffs() = -delta.coeffs();  // the same rotation, w >= 0
    Eigen::Map<Eigen::Matrix<T, 6, 1>> error(residuals);
    error.template head<3>() =
        q_measured.conjugate() * (p_ab - measured_.position.template cast<T>());
    error.template tail<3>() = delta.vec();
    error.applyOnTheLeft(sqrt_information_.template cast<T>());
    return true;
  }

 private:
  Pose measured_;
  Eigen::Matrix<double, 6, 6> sqrt_information_;
};

void Optimize(Graph& graph, bool robust) {
  ceres::Problem problem;
  for (const Edge& edge : graph.edges) {
    Pose& a = graph.vertices[edge.from];
    Pose& b = graph.vertices[edge.to];
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 6, 3, 4, 3, 4>(
        new RelativePoseError(edge.measured, edge.information));
    // Cauchy: a loop closure's pull fades once it is several standard deviations from the rest
    // of the graph, so one wrong loop closure stays wrong alone.
    ceres::LossFunction* loss = edge.loop_closure && robust ? new ceres::CauchyLoss(1.0) : nullptr;
    problem.AddResidualBlock(cost, loss, a.position.data(), a.rotation.coeffs().data(),
                             b.position.data(), b.rotation.coeffs().data());
  }
  for (auto& [id, pose] : graph.vertices) {
    if (problem.HasParameterBlock(pose.rotation.coeffs().data())) {
      problem.SetManifold(pose.rotation.coeffs().data(), new ceres::EigenQuaternionManifold);
    }
  }
  for (int id : graph.fixed) {
    Pose& pose = graph.vertices[id];
    if (!problem.HasParameterBlock(pose.position.data())) continue;
    problem.SetParameterBlockConstant(pose.position.data());
    problem.SetParameterBlockConstant(pose.rotation.coeffs().data());
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = 200;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  std::cout << "Ceres: " << summary.BriefReport() << "\n";
  if (!summary.IsSolutionUsable()) Fail("the optimization failed: " + summary.message);
}

// A TUM trajectory's poses by time stamp.
std::map<double, Pose> ReadTum(const std::string& path) {
  std::ifstream in(path);
  if (!in) Fail(path + ": cannot be read");
  std::map<double, Pose> poses;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    double t, x, y, z, qx, qy, qz, qw;
    if (line.empty() || line[0] == '#') continue;
    if (!(fields >> t >> x >> y >> z >> qx >> qy >> qz >> qw))
      Fail(path + ": not a TUM trajectory");
    poses[t] = {{x, y, z}, Eigen::Quaterniond(qw, qx, qy, qz).normalized()};
  }
  return poses;
}

// The absolute trajectory error: the RMSE of the positions after the rigid motion that best
// aligns them on `truth`'s (Umeyama; TUM's ATE), in metres, and the RMSE of the rotations' angles
// after the rotation that best aligns them (the chordal mean), in degrees.
struct TrajectoryError {
  double metres = 0, degrees = 0;
};

TrajectoryError Ate(const std::vector<Pose>& estimate, const std::vector<Pose>& truth) {
  Eigen::Matrix3Xd from(3, estimate.size()), to(3, truth.size());
  Eigen::Matrix3d rotations = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < estimate.size(); ++i) {
    from.col(i) = estimate[i].position, to.col(i) = truth[i].position;
    rotations +=
        truth[i].rotation.toRotationMatrix() * estimate[i].rotation.toRotationMatrix().transpose();
  }
  const Eigen::Matrix4d alignment = Eigen::umeyama(from, to, false);
  const Eigen::Matrix3Xd aligned =
      (alignment.topLeftCorner<3, 3>() * from).colwise() + alignment.topRightCorner<3, 1>();
  // The rotation nearest the sum (its SVD's U V^T, with the determinant +1).
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(rotations, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d sign = Eigen::Matrix3d::Identity();
  sign(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
  const Eigen::Quaterniond turn(svd.matrixU() * sign * svd.matrixV().transpose());
  double squared_angles = 0;
  for (size_t i = 0; i < estimate.size(); ++i) {
    const Eigen::Quaterniond error = truth[i].rotation.conjugate() * turn * estimate[i].rotation;
    const double angle = Eigen::AngleAxisd(error).angle() * 180 / M_PI;
    squared_angles += angle * angle;
  }
  return {std::sqrt((aligned - to).colwise().squaredNorm().mean()),
          std::sqrt(squared_angles / estimate.size())};
}

}  // namespace

int main(int argc, char** argv) {
  const bool robust = !(argc > 1 && std::string(argv[1]) == "--no-robust-loss");
  if (!robust) --argc, ++argv;
  if (argc < 4 || argc > 5) {
    std::cerr << "usage: 03_pose_graph [--no-robust-loss] GRAPH.g2o MAP.db OPTIMIZED.txt "
                 "[TRUTH.txt]\n";
    return 2;
  }
  Graph graph = ReadG2o(argv[1]);
  std::map<int, double> stamps;
  try {
    for (const memloop::MapImage& image : memloop::ReadMapImages(argv[2])) {
      stamps[image.index] = image.timestamp;
    }
  } catch (const std::exception& error) {
    Fail(error.what());
  }
  const std::map<int, Pose> odometry = graph.vertices;
  int loop_closures = 0;
  for (const Edge& edge : graph.edges) loop_closures += edge.loop_closure;
  std::cout << graph.vertices.size() << " vertices, " << graph.edges.size() - loop_closures
            << " odometry edges, " << loop_closures << " loop closures\n";
  Optimize(graph, robust);

  std::ofstream out(argv[3]);
  for (const auto& [id, pose] : graph.vertices) {
    if (!stamps.count(id)) Fail(std::string(argv[2]) + ": holds no image " + std::to_string(id));
    char line[256];
    std::snprintf(line, sizeof(line), "%.6f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", stamps[id],
                  pose.position.x(), pose.position.y(), pose.position.z(), pose.rotation.x(),
                  pose.rotation.y(), pose.rotation.z(), pose.rotation.w());
    out << line;
  }
  if (!out) Fail(std::string(argv[3]) + ": cannot be written");
  std::cout << "optimized trajectory: " << argv[3] << "\n";
  if (argc < 5) return 0;

  // The truth at each vertex's time stamp (the nearest within 10 ms).
  const std::map<double, Pose> truth = ReadTum(argv[4]);
  std::vector<Pose> true_poses, before, after;
  for (const auto& [id, pose] : graph.vertices) {
    const auto found = truth.lower_bound(stamps[id] - 0.01);
    if (found == truth.end() || found->first > stamps[id] + 0.01) continue;
    true_poses.push_back(found->second);
    before.push_back(odometry.at(id));
    after.push_back(pose);
  }
  if (true_poses.size() < 3) Fail(std::string(argv[4]) + ": too few poses at the vertices' times");
  const TrajectoryError error_before = Ate(before, true_poses),
                        error_after = Ate(after, true_poses);
  std::printf(
      "ATE over %zu poses: odometry %.4f m, optimized %.4f m; rotation RMSE: odometry "
      "%.2f deg, optimized %.2f deg\n",
      true_poses.size(), error_before.metres, error_after.metres, error_before.degrees,
      error_after.degrees);
  return 0;
}
