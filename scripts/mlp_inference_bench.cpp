// The learned predictor's inference, Eigen against libtorch, both
// measured (docs/learned.md has the numbers). Same
// perceptron shape as the model (102 -> 64 -> 64 -> 1, ReLU), random
// weights, batches of 768 rows (256 elements x 3 channels, as the
// predictor runs it) or as given, one thread.
// Not part of the build (libtorch is not a dependency):
//   g++ -O2 -std=c++17 scripts/mlp_inference_bench.cpp -I/usr/include/eigen3 \
//       -I/usr/include/torch/csrc/api/include -ltorch -ltorch_cpu -lc10 -o /tmp/mlp_bench
//   /tmp/mlp_bench [rows] [batch]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <Eigen/Core>
#include <torch/torch.h>

int main(int argc, char** argv) {
    const int inputs = 102, hidden = 64;
    const int batch = argc > 2 ? std::atoi(argv[2]) : 768;
    const long rows = argc > 1 ? std::atol(argv[1]) : 318634L * 3;
    torch::set_num_threads(1);
    Eigen::setNbThreads(1);
    torch::manual_seed(1);
    const torch::Tensor w1 = torch::randn({hidden, inputs}) * 0.1, b1 = torch::randn({hidden}) * 0.1;
    const torch::Tensor w2 = torch::randn({hidden, hidden}) * 0.1, b2 = torch::randn({hidden}) * 0.1;
    const torch::Tensor w3 = torch::randn({1, hidden}) * 0.1, b3 = torch::randn({1}) * 0.1;
    const torch::Tensor x = torch::rand({batch, inputs});
    using Matrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    auto map = [](const torch::Tensor& t) {
        return Eigen::Map<const Matrix>(t.data_ptr<float>(), t.size(0), t.dim() > 1 ? t.size(1) : 1);
    };
    const Matrix W1 = map(w1), W2 = map(w2), W3 = map(w3);
    const Eigen::VectorXf B1 = map(b1), B2 = map(b2), B3 = map(b3);
    const Matrix X = map(x);

    double checksum = 0;
    auto t0 = std::chrono::steady_clock::now();
    for (long done = 0; done < rows; done += batch) {
        Eigen::MatrixXf a = W1 * X.transpose();
        a.colwise() += B1;
        a = a.cwiseMax(0.0f);
        Eigen::MatrixXf b = W2 * a;
        b.colwise() += B2;
        b = b.cwiseMax(0.0f);
        Eigen::MatrixXf y = W3 * b;
        y.colwise() += B3;
        checksum += y(0, 0);
    }
    const double eigen_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    torch::NoGradGuard noGrad;
    t0 = std::chrono::steady_clock::now();
    for (long done = 0; done < rows; done += batch) {
        torch::Tensor a = torch::relu(torch::addmm(b1, x, w1.t()));
        torch::Tensor b = torch::relu(torch::addmm(b2, a, w2.t()));
        torch::Tensor y = torch::addmm(b3, b, w3.t());
        checksum += y[0][0].item<float>();
    }
    const double torch_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("rows %ld, batch %d, one thread: Eigen %.3f s, libtorch %.3f s, libtorch/Eigen %.2f (checksum %.3f)\n",
                rows, batch, eigen_s, torch_s, torch_s / eigen_s, checksum);
    return 0;
}
