// Runs a scene file with the installed contact library and prints what the run did:
//     scene SCENE.toml
// Exit code 0 when every step was solved to its accuracy (status "completed").
#include "contact/scene.hpp"

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s SCENE.toml\n", argv[0]);
    return 2;
  }
  try {
    const contact::Scene scene = contact::LoadScene(argv[1]);
    const contact::SceneResult result = contact::RunScene(scene, /*progress=*/false);
    const contact::DynamicSummary& s = result.summary;
    std::printf("%s: %s after %d steps, %d Newton iterations, max penetration %.3g m\n",
                scene.name.c_str(), contact::ToString(s.status), s.steps,
                s.newton_iterations, s.max_penetration);
    for (const std::string& file : result.files_written)
      std::printf("wrote %s\n", file.c_str());
    return s.status == contact::DynamicStatus::kCompleted ? 0 : 1;
  } catch (const std::exception& e) {  // a refused scene names the key and the range
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
