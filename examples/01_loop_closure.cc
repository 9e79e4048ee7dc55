// Lesson 1: detect loop closures in a sequence of images.
//
// Steps: (1) choose options, (2) create a Detector with a new map file, (3) give it images in
// acquisition order, (4) read each Result, (5) close the map. The images here come from the
// built-in generated route, so the example runs anywhere; a real program would read a folder
// (memloop::ImageSequence::Open) or a camera.
//
// Usage: 01_loop_closure [MAP_FILE]
#include <memloop/memloop.h>          // Detector, Options, Result
#include <memloop/synthetic_route.h>  // SyntheticRoute (memloop::synthetic)

#include <cstdio>
#include <iostream>

int main(int argc, char** argv) {
  const std::string map_file = argc > 1 ? argv[1] : "example_map.db";
  std::remove(map_file.c_str());  // a run starts a new map

  // (1) The paper's defaults, with the time limit off so the run repeats exactly.
  memloop::Options options;
  options.memory.time_limit_ms = 0;
  try {
    // (2) The detector writes its Long-Term Memory to map_file.
    memloop::Detector detector(options, map_file);
    // (3) A route that passes the same places again.
    const memloop::SyntheticRoute route;
    int loop_closures = 0;
    for (int index = 0; index < route.size(); ++index) {
      // (4) One call per image.
      const memloop::Result result = detector.Process(route.Render(index), index);
      if (result.HasLoopClosure()) {
        ++loop_closures;
        if (loop_closures <= 5) std::cout << result.Brief() << "\n";
      }
    }
    // (5) Store the rest of the map.
    detector.Close();
    std::cout << loop_closures << " loop closures in " << route.size() << " images; map in "
              << map_file << "\n";
    return loop_closures > 0 ? 0 : 1;
  } catch (const memloop::Error& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
}
