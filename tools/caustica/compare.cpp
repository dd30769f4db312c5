// caustica compare: how far one image is from another (docs/accuracy.md).
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "core/error.h"
#include "flags.h"
#include "io/image_io.h"
#include "reference/image_metrics.h"

namespace caustica::cli {

int cmd_compare(Args& args) {
  std::vector<std::string> files;
  double sigma = 1.5, max_l1 = -1;
  bool json = false;
  const FlagTable flags{blur_flag(sigma, "Gaussian sigma in pixels for relative_l1 and energy_ratio (default 1.5; 0: none)"),
                        switch_flag("--json", "print the metrics as JSON", json),
                        number_flag("--max-l1", "X", "exit 1 when relative_l1 is above X (for tests)", max_l1, 0, 1e30)};
  if (args.wants_help()) {
    std::cout << "usage: caustica compare A B [--blur SIGMA] [--json] [--max-l1 X]\n\n"
                 "Compares image A (an engine output, e.g. --dump caustics=A.exr) with image B (the reference, e.g.\n"
                 "caustica reference --photons), both the same size (docs/accuracy.md):\n"
                 "  relative_l1    sum |A - B| / sum |B| on luminance after both are blurred by the same Gaussian\n"
                 "  energy_ratio   sum A / sum B on luminance (above 1: A has more energy than B)\n"
                 "  shape_l1       the same L1 with each image divided by its own sum (0 to 2): misplaced energy only\n"
                 "  mean_error, rms_error, max_error         |A - B| over the unblurred colour values\n"
                 "  psnr                                    20 log10(peak / rms_error) in dB, the peak B's largest colour value\n"
                 "  nonfinite_a, nonfinite_b                NaN or Inf values in each image\n\n"
                 "options:\n"
              << flags.help();
    return 0;
  }
  flags.parse(args, [&files](const std::string& file) { files.push_back(file); });
  if (files.size() != 2) throw UsageError("compare needs two images, A and B; see caustica compare --help");
  const io::ImageData a = io::read_image(files[0]), b = io::read_image(files[1]);
  const auto c = reference::compare_images(a, b, sigma);
  const nlohmann::json metrics = {{"relative_l1", c.relative_l1}, {"energy_ratio", c.energy_ratio}, {"shape_l1", c.shape_l1},
                                  {"mean_error", c.mean_error},   {"rms_error", c.rms_error},       {"psnr", c.psnr},
                                  {"max_error", c.max_error},     {"nonfinite_a", c.nonfinite_a},   {"nonfinite_b", c.nonfinite_b},
                                  {"blur_sigma", sigma}};
  if (json) {
    std::cout << metrics.dump(2) << "\n";
  } else {
    std::printf(
        "relative_l1   %.6g   (blur sigma %.3g px)\nenergy_ratio  %.6g\nshape_l1      %.6g\nmean_error    %.6g\nrms_error     %.6g\npsnr   "
        "       %.4g dB\n"
        "max_error     %.6g\nnonfinite     %llu in A, %llu in B\n",
        c.relative_l1, sigma, c.energy_ratio, c.shape_l1, c.mean_error, c.rms_error, c.psnr, c.max_error,
        static_cast<unsigned long long>(c.nonfinite_a), static_cast<unsigned long long>(c.nonfinite_b));
  }
  if (max_l1 >= 0 && !(c.relative_l1 <= max_l1)) {
    std::fprintf(stderr, "caustica: %s: relative L1 %.6g against %s is above --max-l1 %.6g\n", files[0].c_str(), c.relative_l1,
                 files[1].c_str(), max_l1);
    return 1;
  }
  return 0;
}

}  // namespace caustica::cli
