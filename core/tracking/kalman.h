// A constant-velocity Kalman filter for one tracked point on the field (Eigen). Tuned high-gain:
// a hand changes direction within a frame or two, and lagging behind it costs more than
// passing the measurement's few millimetres of noise through.
#pragma once

#include <Eigen/Dense>

namespace quantum::tracking {

class PointFilter {
 public:
  // acceleration: white-noise acceleration density (m/s^2) the motion model allows;
  // measurement: standard deviation of a measured position (m).
  PointFilter(double acceleration, double measurement) : q_(acceleration * acceleration), r_(measurement * measurement) {}

  bool started() const { return started_; }
  void reset() { started_ = false; }

  // Moves the estimate dt seconds on. Without a correction after it, that is all a missed frame gets.
  void predict(double dt) {
    if (!started_) return;
    Eigen::Matrix4d f = Eigen::Matrix4d::Identity();
    f(0, 2) = f(1, 3) = dt;
    // Discrete white-noise acceleration, per axis [dt^4/4 dt^3/2; dt^3/2 dt^2] * q.
    Eigen::Matrix4d q = Eigen::Matrix4d::Zero();
    const double a = dt * dt * dt * dt / 4, b = dt * dt * dt / 2, c = dt * dt;
    q(0, 0) = q(1, 1) = a, q(0, 2) = q(2, 0) = q(1, 3) = q(3, 1) = b, q(2, 2) = q(3, 3) = c;
    x_ = f * x_;
    p_ = f * p_ * f.transpose() + q * q_;
  }

  void correct(double mx, double my) {
    if (!started_) {
      x_ << mx, my, 0, 0;
      p_ = Eigen::Matrix4d::Identity() * r_;
      p_(2, 2) = p_(3, 3) = 1;  // no idea of the speed yet: up to about 1 m/s
      started_ = true;
      return;
    }
    Eigen::Matrix<double, 2, 4> h = Eigen::Matrix<double, 2, 4>::Zero();
    h(0, 0) = h(1, 1) = 1;
    const Eigen::Matrix2d s = h * p_ * h.transpose() + Eigen::Matrix2d::Identity() * r_;
    const Eigen::Matrix<double, 4, 2> k = p_ * h.transpose() * s.inverse();
    x_ += k * (Eigen::Vector2d(mx, my) - h * x_);
    p_ = (Eigen::Matrix4d::Identity() - k * h) * p_;
  }

  double x() const { return x_(0); }
  double y() const { return x_(1); }
  double vx() const { return x_(2); }
  double vy() const { return x_(3); }

 private:
  double q_, r_;
  bool started_ = false;
  Eigen::Vector4d x_ = Eigen::Vector4d::Zero();
  Eigen::Matrix4d p_ = Eigen::Matrix4d::Identity();
};

}  // namespace quantum::tracking
