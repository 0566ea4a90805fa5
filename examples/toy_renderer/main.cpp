// A toy renderer that balances its frames with multiray::balance. Two fake "devices" are
// threads computing a Mandelbrot image (uneven cost per pixel); the second one computes
// every pixel three times, so it is a third as fast. Each frame: plan, render (both
// devices pull work by the Plan's dispatch rules), report what each did, update.
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include <multiray/balance.h>

namespace mb = multiray::balance;

// The "kernel": iterations until escape, for the pixel of a view that zooms in per frame.
int shade(int x, int y, int w, int h, int frame) {
  const double zoom = 1.0 + 0.05 * frame;
  const double cr = -0.745 + (x - w / 2.0) * 3.0 / (w * zoom);
  const double ci = 0.11 + (y - h / 2.0) * 3.0 / (w * zoom);
  double zr = 0, zi = 0;
  int i = 0;
  for (; i < 400 && zr * zr + zi * zi < 4; ++i) {
    const double t = zr * zr - zi * zi + cr;
    zi = 2 * zr * zi + ci;
    zr = t;
  }
  return i;
}

int main(int argc, char** argv) {
  const std::string spec = argc > 1 ? argv[1] : "hybrid";
  const int frames = argc > 2 ? std::stoi(argv[2]) : 12;
  const int repeat[2] = {1, 3};  // device 1 does every pixel 3 times: a third of the speed
  std::unique_ptr<mb::Balancer> balancer;
  try {
    balancer = mb::make_balancer(spec, 2);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  mb::FrameShape shape{320, 180, 1, {}};
  std::vector<int> image(size_t(shape.width * shape.height));
  std::printf("%s on 2 devices (device 1 is 3x slower), %dx%d\n", balancer->spec().c_str(),
              shape.width, shape.height);
  std::printf("frame  planned shares   rendered shares   device ms        imbalance\n");

  for (int frame = 0; frame < frames; ++frame) {
    const mb::Plan plan = balancer->plan(shape, frame);
    mb::Dispatcher dispatch(plan, shape);  // executes the plan: own list, queue, steals
    mb::FrameStats stats;
    stats.frame = frame;
    stats.shape = shape;
    stats.devices.resize(2);
    std::vector<std::thread> threads;
    for (size_t d = 0; d < 2; ++d)
      threads.emplace_back([&, d] {
        using clock = std::chrono::steady_clock;
        const auto start = clock::now();
        mb::DeviceFrameStats& me = stats.devices[d];
        for (uint32_t id; dispatch.next(int(d), id);) {
          const mb::WorkItem& item = dispatch.items()[id];
          const auto t0 = clock::now();
          for (int r = 0; r < repeat[d]; ++r)
            for (int y = item.rect.y0; y < item.rect.y1; ++y)
              for (int x = item.rect.x0; x < item.rect.x1; ++x)
                image[size_t(y * shape.width + x)] = shade(x, y, shape.width, shape.height, frame);
          const double ms = std::chrono::duration<double, std::milli>(clock::now() - t0).count();
          me.items.push_back({item, ms, double(item.rect.area()), ms, id});
          me.pixels += double(item.rect.area());
        }
        me.samples = me.pixels;  // one sample per pixel
        me.time_ms = me.busy_ms =
            std::chrono::duration<double, std::milli>(clock::now() - start).count();
      });
    for (auto& t : threads) t.join();
    balancer->update(stats);

    const double total = stats.devices[0].pixels + stats.devices[1].pixels;
    std::printf("%5d  %.3f / %.3f    %.3f / %.3f     %6.1f / %6.1f  %6.1f%%\n", frame,
                plan.ratios[0], plan.ratios[1], stats.devices[0].pixels / total,
                stats.devices[1].pixels / total, stats.devices[0].time_ms,
                stats.devices[1].time_ms, 100 * mb::imbalance(stats));
  }
  long checksum = 0;
  for (int v : image) checksum += v;
  std::printf("image checksum %ld (the same for every balancer)\n", checksum);
}
