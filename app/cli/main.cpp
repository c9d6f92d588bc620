// labeloctomap: the command-line program (needs no display).
#include <algorithm>
#include <csignal>
#include <cstring>
#include <iostream>
#include <new>
#include <string>

#include "args.hpp"
#include "commands.hpp"
#include "lom/atomic_file.hpp"
#include "lom/error.hpp"

namespace {

struct Command {
  const char* name;
  int (*run)(const lom::cli::Words&);
  const char* usage;
};

const Command kCommands[] = {
    {"info", lom::cli::runInfo, "info SEQ | info MAP.ot        summary of a sequence or a map"},
    {"validate", lom::cli::runValidate,
     "validate SEQ                  check every file of a sequence; non-zero exit on problems"},
    {"synth", lom::cli::runSynth,
     "synth --out DIR [--seed S] [--objects N] [--frames F] [--views V] [--width W]\n"
     "      [--height H] [--no-noise] [--perfect-segmenter]\n"
     "                                write a synthetic shelf-bin sequence with annotations"},
    {"fuse", lom::cli::runFuse,
     "fuse SEQ --out MAP.ot [--resolution R] [--max-range M] [--p-miss P] [--threshold T]\n"
     "     [--candidates 0,8,19 | --candidates none] [--frames A:B] [--segmenter MODEL.onnx]\n"
     "     [--start-from EARLIER.ot] [--frame-memory GIB] [--quiet]\n"
     "                                fuse a sequence into a LabelOctoMap"},
    {"score", lom::cli::runScore,
     "score SEQ --annotations BOXES.json|BOXES.yaml --out DIR [--map MAP.ot]\n"
     "      [--resolution R] [--max-range M] [--p-miss P] [--threshold T] [--candidates ...]\n"
     "      [--frames A:B] [--iou exact|center] [--segmenter MODEL.onnx] [--frame-memory GIB]\n"
     "      [--quiet]\n"
     "      | score --batch LIST.txt --out DIR [the same options, without SEQ, --annotations and "
     "--map]\n"
     "                                per-object IU_3d against projection baselines"},
    {"export", lom::cli::runExport,
     "export MAP.ot --format ply|obj|stl|pcd|ot|bt|objects [--per-label] [--labels 8,19]\n"
     "       [--smooth] [--points] [--native] [--no-merge] [--level] [--sequence SEQ] --out PATH\n"
     "       | export MAP.ot --voxels OUT.pcd   (all options: labeloctomap help export)\n"
     "                                write meshes, point clouds, octrees or object boxes"},
    {"render", lom::cli::runRender,
     "render MAP.ot --out view.png [--camera SEQ:INDEX | --azimuth A --elevation E --up X,Y,Z]\n"
     "       [--frame bulk|all] [--size 1280x960] [--labels 8,19] [--flat]\n"
     "       [--colour labels|height] [--colour score --annotations BOXES.json [--iou "
     "exact|center]]\n"
     "                                render the map offscreen to a PNG (needs X or Xvfb)"},
    {"import", lom::cli::runImport,
     "import KIND SRC --out SEQ [--intrinsics fx,fy,cx,cy|FILE] [--every N] [--overwrite] ...\n"
     "                                convert a ROS bag or dataset folder to a sequence\n"
     "                                (KIND: auto, rosbag, frames, tum, quaternion, scannet, "
     "apc-shelf;\n"
     "                                all options: labeloctomap import --help)"},
    {"plan", lom::cli::runPlan,
     "plan MAP.ot --target LABEL [--approach x,y,z | --sequence SEQ] [--empty-bin c,c,c,d,d,d]\n"
     "     [--threshold T] [--out plan.json] (all options: labeloctomap help plan)\n"
     "                                which objects to remove before picking the target"},
    {"segment", lom::cli::runSegment,
     "segment SEQ --segmenter MODEL.onnx [--all] [--dtype float32|float16|uint8] [--out-dir DIR]\n"
     "        [--quiet]\n"
     "                                write probability images from a segmentation network"},
};

// "labeloctomap fuse scene --out m.ot" as typed (without quoting).
std::string commandLine(int argc, char** argv) {
  std::string line = "labeloctomap";
  for (int i = 1; i < argc; ++i) line += std::string(" ") + argv[i];
  return line;
}

void printUsage(std::ostream& out) {
  out << "usage: labeloctomap COMMAND [ARGS] | labeloctomap --version\n\ncommands:\n";
  for (const auto& c : kCommands) out << "  " << c.usage << "\n";
}

// What takes less memory, for the command that ran out: only the commands
// that fuse have a --resolution to coarsen.
std::string lessMemoryAdvice(const std::string& command) {
  if (command == "fuse" || command == "score")
    return "smaller option values, e.g. a coarser --resolution or a shorter --max-range, need "
           "less memory";
  if (command == "render")
    return "a smaller --size needs less; so does a map of fewer nodes, fused with coarser voxels";
  if (command == "info" || command == "export" || command == "plan")
    return "the map needs more memory to read than the system allows (about 45 bytes per node, "
           "labeloctomap info gives the count); free memory or raise ulimit -v, or fuse the "
           "sequence with coarser voxels";
  return "free memory or raise ulimit -v";
}

// A command's usage on standard output (COMMAND --help, help COMMAND).
int printCommandHelp(const Command& command) {
  if (std::string(command.name) == "import")
    std::cout << lom::cli::importHelp();
  else
    std::cout << "usage: labeloctomap " << command.usage << "\n"
              << lom::cli::commandOptionsHelp(command.name);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Beyond a file-size limit (ulimit -f, as batch systems set) the kernel
  // kills a writer with SIGXFSZ, leaving its temporary files behind; ignored,
  // the write fails with EFBIG and the command reports it and cleans up.
  std::signal(SIGXFSZ, SIG_IGN);
  // Ctrl-C or a kill in the middle of a write removes the temporary files.
  lom::removePendingOutputsOnSignals();
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
      (!std::strcmp(argv[1], "help") && argc == 2)) {
    printUsage(argc < 2 ? std::cerr : std::cout);
    return argc < 2 ? 2 : 0;
  }
  // "help fuse" as "fuse --help" (git's habit); an unknown name below.
  if (!std::strcmp(argv[1], "help")) {
    if (argc > 3) {
      std::cerr << "labeloctomap help: expects one command name, got " << argc - 2 << " words\n";
      printUsage(std::cerr);
      return 2;
    }
    for (const auto& c : kCommands)
      if (c.name == std::string(argv[2])) return printCommandHelp(c);
    std::cerr << "labeloctomap help: unknown command '" << argv[2] << "'\n";
    printUsage(std::cerr);
    return 2;
  }
  // As the studio's --version: the version of the build, for bug reports.
  if (!std::strcmp(argv[1], "--version") || !std::strcmp(argv[1], "-v")) {
    if (argc > 2) {
      std::cerr << "labeloctomap " << argv[1] << ": takes no arguments, got '" << argv[2] << "'\n";
      return 2;
    }
    std::cout << "labeloctomap " << LOM_VERSION << "\n";
    return 0;
  }
  const std::string name = argv[1];
  lom::cli::Words words(argv + 2, argv + argc);
  for (const auto& c : kCommands) {
    if (name != c.name) continue;
    if (std::any_of(words.begin(), words.end(), lom::cli::isHelpWord)) return printCommandHelp(c);
    try {
      const int status = c.run(words);
      // What the command printed (tables, "wrote ..." lines) must have
      // reached standard output: `score ... > table.txt` on a full disk is a
      // failure, not an empty file and success.
      std::cout.flush();
      if (!std::cout) {
        std::cerr << "labeloctomap " << name
                  << ": error: could not write to standard output (a full disk?); files the "
                     "command wrote are kept\n";
        return status == 0 ? 1 : status;
      }
      return status;
    } catch (const std::bad_alloc&) {
      std::cerr << "labeloctomap " << name << ": out of memory while running '"
                << commandLine(argc, argv) << "' (" << lessMemoryAdvice(name) << ")\n";
      return 1;
    } catch (const lom::cli::UsageError& e) {
      std::cerr << "labeloctomap " << name << ": " << e.what() << "\nusage: labeloctomap "
                << c.usage << "\n";
      return 2;
    } catch (const lom::ValidationError& e) {
      std::cerr << "labeloctomap " << name << ": " << e.what() << "\n";
      return 1;
    } catch (const std::exception& e) {
      std::cerr << "labeloctomap " << name << ": error: " << e.what() << "\n";
      return 1;
    }
  }
  std::cerr << "labeloctomap: unknown command '" << name << "'\n";
  printUsage(std::cerr);
  return 2;
}
