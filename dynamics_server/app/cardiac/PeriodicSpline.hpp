#pragma once
// Periodic cubic spline interpolation (paper §5.2: "a curve was fitted to the averaged pressure
// data using cubic spline interpolation"): through K equally spaced knots over one period, with
// continuous first and second derivatives across the period's ends.
#include <Eigen/Dense>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace bop::app {

class PeriodicSpline {
public:
    // values[k] at x = k / K of a period 1 (K >= 3).
    explicit PeriodicSpline(std::vector<double> values) : y_(std::move(values)) {
        const int k = int(y_.size());
        if (k < 3) throw std::invalid_argument("periodic spline: at least 3 knots expected");
        // Second derivatives m: m[i-1] + 4 m[i] + m[i+1] = 6 (y[i-1] - 2 y[i] + y[i+1]) / dx^2, cyclic.
        const double dx = 1.0 / k;
        Eigen::MatrixXd a = Eigen::MatrixXd::Zero(k, k);
        Eigen::VectorXd b(k);
        for (int i = 0; i < k; ++i) {
            a(i, (i + k - 1) % k) += 1;
            a(i, i) += 4;
            a(i, (i + 1) % k) += 1;
            b(i) = 6 * (y_[std::size_t((i + k - 1) % k)] - 2 * y_[std::size_t(i)] + y_[std::size_t((i + 1) % k)]) /
                   (dx * dx);
        }
        const Eigen::VectorXd m = a.partialPivLu().solve(b);
        m_.assign(m.data(), m.data() + k);
    }

    // The curve at x (any real: taken modulo 1).
    double operator()(double x) const {
        const int k = int(y_.size());
        const double dx = 1.0 / k, u = (x - std::floor(x)) * k;
        const int i = std::min(int(u), k - 1), j = (i + 1) % k;
        const double t = u - i, s = 1 - t;
        const double yi = y_[std::size_t(i)], yj = y_[std::size_t(j)], mi = m_[std::size_t(i)], mj = m_[std::size_t(j)];
        return s * yi + t * yj + dx * dx / 6 * ((s * s * s - s) * mi + (t * t * t - t) * mj);
    }

private:
    std::vector<double> y_, m_;
};

}  // namespace bop::app
