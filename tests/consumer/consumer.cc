// A user's program: the installed core library, found with find_package(memloop).
#include <memloop/memloop.h>

#include <iostream>

int main(int argc, char** argv) {
  if (argc < 2) return 2;
  memloop::Options options;
  options.memory.time_limit_ms = 0;
  memloop::Detector detector(options, argv[1]);
  cv::Mat image(240, 320, CV_8UC1);
  cv::randu(image, 0, 256);
  std::cout << memloop::Parameters().size() << " parameters; " << detector.Process(image, 0).Brief()
            << "\n";
  detector.Close();
  return 0;
}
