// Import entry points: kinds and their detection, option checks, the dispatch
// to the importers, and the studio's cached conversion (openSource).
#include "lom/import.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <sstream>

#include "import_internal.hpp"
#include "lom/atomic_file.hpp"

namespace lom {

namespace fs = std::filesystem;
using namespace import_detail;

namespace {

struct KindName {
  SourceKind kind;
  const char* name;
};
constexpr KindName kKindNames[] = {
    {SourceKind::Sequence, "sequence"},     {SourceKind::RosBag, "rosbag"},
    {SourceKind::Frames, "frames"},         {SourceKind::Tum, "tum"},
    {SourceKind::Quaternion, "quaternion"}, {SourceKind::ScanNet, "scannet"},
    {SourceKind::ApcShelf, "apc-shelf"},
};

bool isDir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec);
}
bool isFile(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

bool startsWithRosbagMagic(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[9] = {};
  in.read(magic, 8);
  return std::string(magic, static_cast<size_t>(in.gcount())) == "#ROSBAG ";
}

std::string someEntries(const fs::path& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    names.push_back(entry.path().filename().string() + (entry.is_directory(ec) ? "/" : ""));
    if (names.size() > 200) break;
  }
  std::sort(names.begin(), names.end());
  if (names.empty()) return "an empty folder";
  std::string text;
  for (size_t i = 0; i < names.size() && i < 8; ++i) text += (i ? ", " : "") + names[i];
  if (names.size() > 8) text += ", ...";
  return text;
}

void checkOptions(const ImportOptions& options) {
  auto fail = [](const std::string& field, const std::string& expected, const std::string& found) {
    throw Error("", field, expected, found);
  };
  if (!(options.time_tolerance >= 0.0) || !std::isfinite(options.time_tolerance))
    fail("time_tolerance", "a non-negative number of seconds", formatNumber(options.time_tolerance));
  if (!std::isfinite(options.time_offset))
    fail("time_offset", "a finite number of seconds", formatNumber(options.time_offset));
  if (!(options.label_confidence > 0.0 && options.label_confidence < 1.0))
    fail("label_confidence", "a probability strictly between 0 and 1",
         formatNumber(options.label_confidence));
  if (options.frame_step < 1) fail("frame_step", "at least 1", std::to_string(options.frame_step));
  if (options.depth_scale && (!(*options.depth_scale > 0.0) || !std::isfinite(*options.depth_scale)))
    fail("depth_scale", "a positive number of metres per unit", formatNumber(*options.depth_scale));
  if (options.intrinsics) {
    const auto& c = *options.intrinsics;
    if (!(c.fx > 0.0) || !(c.fy > 0.0) || !std::isfinite(c.cx) || !std::isfinite(c.cy))
      fail("intrinsics", "positive fx, fy and finite cx, cy",
           formatNumber(c.fx) + "," + formatNumber(c.fy) + "," + formatNumber(c.cx) + "," +
               formatNumber(c.cy));
  }
  DepthImage empty;
  filterDepth(empty, options.depth_filter);  // checks the filter options
}

fs::path canonicalPath(const fs::path& path) {
  std::error_code ec;
  return fs::weakly_canonical(fs::absolute(path, ec), ec);
}

bool samePath(const fs::path& a, const fs::path& b) {
  const fs::path ca = canonicalPath(a);
  return !ca.empty() && ca == canonicalPath(b);
}

// Whether `path` is `folder` or lies inside it.
bool sameOrInside(const fs::path& path, const fs::path& folder) {
  const fs::path p = canonicalPath(path), f = canonicalPath(folder);
  if (p.empty() || f.empty()) return false;
  auto pi = p.begin();
  for (auto fi = f.begin(); fi != f.end(); ++fi, ++pi)
    if (pi == p.end() || *pi != *fi) return false;
  return true;
}

std::uint64_t fnv1a(const std::string& text, std::uint64_t hash = 1469598103934665603ull) {
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 1099511628211ull;
  }
  return hash;
}

// Raised whenever the importers write a sequence differently for the same source, so
// that a cache converted by an earlier version (stamps made from frame numbers, one-hot
// probabilities without proba_from_label, label images of colour-and-depth sources
// without label_placeholder; bag poses from stamps rounded through a double, colour
// from the depth camera's own republish, frames posed across long tf gaps; entries
// without the conversion's notes, whose warnings a reused entry could not repeat) is
// converted again instead of reused.
constexpr int kConversionRevision = 5;

// The files named by a TUM list (rgb.txt, depth.txt): "stamp file" lines.
// Lines the import would refuse are its to report; here they name nothing.
std::vector<fs::path> tumListedFiles(const fs::path& list) {
  std::vector<fs::path> files;
  std::ifstream in(list);
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::string stamp, file;
    if (!(words >> stamp >> file) || stamp[0] == '#') continue;
    files.push_back(list.parent_path() / file);
  }
  return files;
}

// Whether the importer of `kind` may read the file or folder `relative`
// (inside the recording's folder, one or two levels deep): only those make a
// conversion, so that boxes, exports, reports, screenshots and renders saved
// beside the frames leave it as it is. Hidden files are editors' and tools'
// own. Folders the layout reads are taken whole; TUM folders are read by
// their lists instead (tumListedFiles).
bool readByImport(SourceKind kind, const fs::path& relative) {
  const std::string top = relative.begin()->string();
  const std::string name = relative.filename().string();
  if (top.empty() || top[0] == '.' || name[0] == '.') return false;
  const bool in_folder = relative.has_parent_path();
  // The files an intrinsics file is looked for among (findIntrinsicsFile).
  const std::string lowered = lower(name);
  const bool intrinsics = !in_folder && relative.extension() == ".txt" &&
                          (lowered.find("intrinsic") != std::string::npos || lowered == "k.txt" ||
                           lowered == "camera.txt" || lowered == "calib.txt");
  switch (kind) {
    case SourceKind::Frames:  // frame-N.{depth,color,label}.png, frame-N.pose.txt
      return (!in_folder && top.rfind("frame-", 0) == 0) || intrinsics;
    case SourceKind::ApcShelf:  // cam.info.txt, frame-N.{color,depth}.png, segm/, masks/
      return top == "segm" || top == "masks" ||
             (!in_folder && (top == "cam.info.txt" || top.rfind("frame-", 0) == 0));
    case SourceKind::Quaternion:
      return top == "depth" || top == "color" || top == "pose.txt" || intrinsics;
    case SourceKind::ScanNet:
      return top == "depth" || top == "color" || top == "pose" || top == "intrinsic" ||
             top == "label-filt" || top == "scannetv2-labels.combined.tsv";
    case SourceKind::Tum:
      return top == "rgb.txt" || top == "depth.txt" || top == "groundtruth.txt";
    case SourceKind::RosBag:
    case SourceKind::Sequence:
      break;
  }
  return false;
}

// What identifies a conversion: the source (names, sizes and modification times
// of the files its import reads, two levels deep, and those a TUM list names;
// a folder by its entries, not its own time, which any new file changes),
// every option and the conversion revision.
std::string conversionFingerprint(const fs::path& source, SourceKind kind,
                                  const ImportOptions& o) {
  std::ostringstream text;
  std::error_code ec;
  text << "revision " << kConversionRevision << '\n';
  text << sourceKindName(kind) << '\n' << fs::weakly_canonical(fs::absolute(source), ec).string() << '\n';
  auto stamp = [&](const fs::path& p) {
    std::error_code e;
    const bool folder = fs::is_directory(p, e);
    const auto time = folder ? 0 : fs::last_write_time(p, e).time_since_epoch().count();
    const auto size = fs::is_regular_file(p, e) ? fs::file_size(p, e) : 0;
    text << p.lexically_relative(source).string() << ' ' << size << ' ' << time << '\n';
  };
  stamp(source);
  if (isDir(source)) {
    std::vector<fs::path> files;
    for (auto it = fs::recursive_directory_iterator(source, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      if (it.depth() >= 1) it.disable_recursion_pending();
      if (!readByImport(kind, it->path().lexically_relative(source))) {
        if (it->is_directory(ec)) it.disable_recursion_pending();
        continue;
      }
      files.push_back(it->path());
    }
    if (kind == SourceKind::Tum)
      for (const char* list : {"rgb.txt", "depth.txt"})
        for (fs::path& file : tumListedFiles(source / list)) files.push_back(std::move(file));
    // ScanNet's label names may lie one or two folders above the scene.
    if (kind == SourceKind::ScanNet)
      for (const fs::path& above : {source.parent_path(), source.parent_path().parent_path()})
        if (isFile(above / "scannetv2-labels.combined.tsv"))
          files.push_back(above / "scannetv2-labels.combined.tsv");
    std::sort(files.begin(), files.end());
    files.erase(std::unique(files.begin(), files.end()), files.end());
    for (const auto& f : files) stamp(f);
  }
  const auto& r = o.rosbag;
  const auto& f = o.depth_filter;
  text << std::setprecision(17) << r.depth_topic << '|' << r.color_topic << '|'
       << r.camera_info_topic << '|' << r.proba_topic << '|' << r.label_topic << '|'
       << r.fixed_frame << '|' << r.camera_frame << '|' << r.no_color << '|' << r.max_pose_gap
       << '|' << o.time_tolerance << '|' << o.time_offset << '|' << f.min_depth << '|'
       << f.max_depth << '|' << f.flying_pixels << '|' << f.flying_pixel_ratio << '|'
       << f.flying_pixel_radius << '|' << f.bilateral_radius << '|' << f.bilateral_sigma_space
       << '|' << f.bilateral_sigma_depth << '|' << o.label_confidence << '|'
       << o.depth_scale.value_or(0.0) << '|' << o.first_frame << '|' << o.frame_step << '|'
       << o.max_frames << '|' << o.write_color << '|';
  if (o.intrinsics)
    text << o.intrinsics->fx << ',' << o.intrinsics->fy << ',' << o.intrinsics->cx << ','
         << o.intrinsics->cy << ',' << o.intrinsics->width << ',' << o.intrinsics->height;
  text << '|';
  if (o.labels)
    // Each name with its length: names may hold commas.
    for (const auto& label : o.labels->all()) text << label.name.size() << ':' << label.name << ',';
  return text.str();
}

}  // namespace

std::string sourceKindName(SourceKind kind) {
  for (const auto& k : kKindNames)
    if (k.kind == kind) return k.name;
  return "unknown";
}

std::optional<SourceKind> sourceKindFromName(const std::string& name) {
  const std::string n = lower(name);
  for (const auto& k : kKindNames)
    if (n == k.name) return k.kind;
  if (n == "bag" || n == "ros") return SourceKind::RosBag;
  if (n == "apc" || n == "apc2016" || n == "shelf") return SourceKind::ApcShelf;
  return std::nullopt;
}

std::vector<SourceKind> importableKinds() {
  return {SourceKind::RosBag,  SourceKind::Frames,  SourceKind::Tum,
          SourceKind::Quaternion, SourceKind::ScanNet, SourceKind::ApcShelf};
}

SourceDetection detectSource(const fs::path& path) {
  SourceDetection d;
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    d.explanation = "no such file or folder";
    return d;
  }
  if (isFile(path)) {
    if (path.filename() == "sequence.json") {
      d.kind = SourceKind::Sequence;
      d.explanation = "a sequence.json file";
    } else if (lower(path.extension().string()) == ".bag" || startsWithRosbagMagic(path)) {
      d.kind = SourceKind::RosBag;
      d.explanation = startsWithRosbagMagic(path) ? "a ROS bag file"
                                                  : "a .bag file (not starting with #ROSBAG)";
    } else {
      d.explanation =
          "a file that is neither a ROS 1 bag (.bag) nor a sequence.json; dataset layouts are "
          "folders";
    }
    return d;
  }
  if (isFile(path / "sequence.json")) {
    d.kind = SourceKind::Sequence;
    d.explanation = "a folder with sequence.json";
  } else if (isFile(path / "cam.info.txt")) {
    d.kind = SourceKind::ApcShelf;
    d.explanation = "an APC shelf & tote scene (cam.info.txt)";
  } else if (isFile(path / "rgb.txt") && isFile(path / "depth.txt")) {
    d.kind = SourceKind::Tum;
    d.explanation = "a TUM RGB-D folder (rgb.txt, depth.txt)";
  } else if (isDir(path / "depth") && isDir(path / "pose")) {
    d.kind = SourceKind::ScanNet;
    d.explanation = "a ScanNet export (depth/, pose/)";
  } else if (isDir(path / "depth") && isFile(path / "pose.txt")) {
    d.kind = SourceKind::Quaternion;
    d.explanation = "a quaternion-pose folder (depth/, pose.txt)";
  } else if (!numberedFiles(path, "frame-", ".depth.png").empty()) {
    d.kind = SourceKind::Frames;
    d.explanation = "a frames folder (frame-NNNNNN.depth.png)";
  } else {
    d.explanation =
        "none of: sequence.json (sequence), cam.info.txt (apc-shelf), rgb.txt + depth.txt (tum), "
        "depth/ + pose/ (scannet), depth/ + pose.txt (quaternion), frame-NNNNNN.depth.png "
        "(frames); found " +
        someEntries(path);
  }
  return d;
}

namespace {

// "  frame: reason" lines, at most `max_listed`, then how many more.
void listSkipped(std::ostream& out, const std::vector<SkippedFrame>& skipped, size_t max_listed) {
  for (size_t i = 0; i < skipped.size() && i < max_listed; ++i)
    out << "  " << skipped[i].frame << ": " << skipped[i].reason << "\n";
  if (skipped.size() > max_listed) out << "  ... and " << skipped.size() - max_listed << " more\n";
}

}  // namespace

bool isImportWarning(const std::string& note) {
  return note.rfind(kWarningNote, 0) == 0 || note.rfind(kDefaultTumIntrinsicsNote, 0) == 0;
}

std::vector<std::string> ImportReport::warnings() const {
  std::vector<std::string> found;
  std::copy_if(notes.begin(), notes.end(), std::back_inserter(found), isImportWarning);
  return found;
}

std::string ImportReport::text(size_t max_skipped_listed) const {
  std::ostringstream out;
  out << (cancelled ? "cancelled after " : "imported ") << frames_written << " of "
      << frames_found << " frames (" << sourceKindName(kind) << ") from " << source.string();
  if (!cancelled) out << " into " << output.string();
  out << "\n";
  if (!skipped.empty()) {
    out << "skipped " << skipped.size() << (skipped.size() == 1 ? " frame:\n" : " frames:\n");
    listSkipped(out, skipped, max_skipped_listed);
  }
  if (!notes.empty()) {
    out << "notes:\n";
    for (const auto& note : notes) out << "  " << note << "\n";
  }
  return out.str();
}

CameraIntrinsics parseIntrinsics(const std::string& text_or_file) {
  if (isFile(text_or_file))
    return intrinsicsFromNumbers(readNumbers(text_or_file), text_or_file);
  std::vector<double> numbers;
  try {
    numbers = parseNumbers(text_or_file, "", 0);
  } catch (const Error&) {
    std::error_code ec;
    const auto status = fs::status(text_or_file, ec);
    throw Error(
        text_or_file, "intrinsics", "fx,fy,cx,cy or an existing file with the camera matrix",
        fs::is_directory(status) ? "a folder, not a file"
        : fs::exists(status)     ? "a special file (a device, FIFO or socket), not a regular file"
                                 : "neither numbers nor a file");
  }
  if (numbers.size() != 4)
    throw Error(text_or_file, "intrinsics", "4 numbers fx,fy,cx,cy or a file with the camera matrix",
                std::to_string(numbers.size()) + " numbers");
  return intrinsicsFromNumbers(numbers, text_or_file);
}

ImportReport importSource(std::optional<SourceKind> kind, const fs::path& source,
                          const fs::path& out_folder, const ImportOptions& options,
                          const ImportProgressCallback& progress) {
  std::error_code ec;
  if (!fs::exists(source, ec))
    throw Error(source.string(), "source", "an existing file or folder", "no such file or folder");
  if (!kind) {
    const SourceDetection detection = detectSource(source);
    if (!detection.kind)
      throw Error(source.string(), "kind", "a ROS bag or a known dataset layout",
                  detection.explanation);
    kind = detection.kind;
  }
  if (*kind == SourceKind::Sequence)
    throw Error(source.string(), "kind", "a recording to convert",
                "a sequence already (open or fuse it directly)");
  if (samePath(source, out_folder))
    throw Error(out_folder.string(), "output", "a folder other than the source", "the source itself");
  // The import replaces the sequence file and the frame folders of its
  // output: a source among them would be deleted with them.
  for (const char* part : {"sequence.json", "depth", "color", "proba", "label"})
    if (sameOrInside(source, out_folder / part))
      throw Error(source.string(), "source",
                  "a recording outside the files the import writes in " + out_folder.string() +
                      " (sequence.json and the depth, color, proba and label folders)",
                  "a path in " + (out_folder / part).string());
  checkOptions(options);

  ImportReport report;
  report.kind = *kind;
  report.source = source;
  report.output = out_folder;
  SequenceWriter writer(out_folder, options, report, progress);
  switch (*kind) {
    case SourceKind::RosBag:
      importRosbag(source, options, writer);
      break;
    case SourceKind::Frames:
      importFrames(source, options, writer);
      break;
    case SourceKind::Tum:
      importTum(source, options, writer);
      break;
    case SourceKind::Quaternion:
      importQuaternion(source, options, writer);
      break;
    case SourceKind::ScanNet:
      importScanNet(source, options, writer);
      break;
    case SourceKind::ApcShelf:
      importApcShelf(source, options, writer);
      break;
    case SourceKind::Sequence:
      break;
  }
  writer.finish(source.string());
  return report;
}

fs::path defaultImportCacheRoot() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return fs::path(xdg) / "labeloctomap" / "imports";
  if (const char* home = std::getenv("HOME"); home && *home)
    return fs::path(home) / ".cache" / "labeloctomap" / "imports";
  return fs::temp_directory_path() / "labeloctomap-imports";
}

namespace {

constexpr const char* kSkippedFramesFile = "skipped-frames.txt";
constexpr const char* kColourLeftOutFile = "colour-left-out.txt";

// The conversion's notes as kept in its entry, one a line: a line break
// inside one (from a message quoted in it) becomes a space.
std::vector<std::string> notesOneALine(std::vector<std::string> notes) {
  for (std::string& note : notes) std::replace(note.begin(), note.end(), '\n', ' ');
  return notes;
}

std::vector<std::string> readNotes(const fs::path& file) {
  std::vector<std::string> notes;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) notes.push_back(line);
  return notes;
}

// The conversion's notes on colour images left out (frames kept without
// colour), one per line; empty when there are none.
std::string colourLeftOutText(const ImportReport& report) {
  std::string text;
  for (const std::string& note : report.notes)
    if (note.rfind(kUnreadableColourNote, 0) == 0) text += note + "\n";
  return text;
}

// A cached conversion that can still be opened: its sequence reads and every
// frame file it names is there (an entry damaged by hand or by a full disk is
// converted again instead of failing on every open). Nothing otherwise.
std::optional<Sequence> readableCacheEntry(const fs::path& folder) {
  try {
    Sequence sequence = loadSequence(folder);
    for (const fs::path& file : frameFilesOf(sequence))
      if (!isFile(file)) return std::nullopt;
    return sequence;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// Import cache entries not opened for this long are removed when another
// recording is converted (the cache would otherwise only grow: every changed
// recording or option set is a new entry). Leftovers of conversions that
// were interrupted (a crash, a kill) go after a day.
constexpr auto kUnusedEntryAge = std::chrono::hours(24 * 30);
constexpr auto kLeftoverAge = std::chrono::hours(24);

// What a conversion writes into its entry. An entry holding anything else
// (boxes that earlier versions saved there, a user's own files) is never
// removed by the pruning.
bool onlyConversionFiles(const fs::path& entry) {
  std::error_code ec;
  for (auto it = fs::directory_iterator(entry, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name != "sequence.json" && name != "depth" && name != "color" && name != "proba" &&
        name != "label" && name != kSkippedFramesFile && name != kColourLeftOutFile &&
        name != kImportNotesFile)
      return false;
  }
  return !ec;
}

// Removes the cache's entries unused for kUnusedEntryAge (an entry's folder
// time is its last open: openSource sets it) and interrupted conversions'
// leftovers, except `keep`. Best effort: what cannot be removed stays.
void pruneImportCache(const fs::path& root, const fs::path& keep) {
  const auto now = fs::file_time_type::clock::now();
  std::error_code ec;
  std::vector<fs::path> old;
  for (auto it = fs::directory_iterator(root, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    std::error_code e;
    if (!it->is_directory(e) || it->is_symlink(e) || it->path() == keep) continue;
    const std::string name = it->path().filename().string();
    const auto time = fs::last_write_time(it->path(), e);
    if (e) continue;
    const bool leftover = name.rfind(".partial-", 0) == 0 || name.rfind(".stale-", 0) == 0;
    if (leftover
            ? now - time > kLeftoverAge
            : name[0] != '.' && now - time > kUnusedEntryAge && onlyConversionFiles(it->path()))
      old.push_back(it->path());
  }
  for (const fs::path& entry : old) {
    std::error_code e;
    const std::string name = entry.filename().string();
    if (name[0] == '.') {
      fs::remove_all(entry, e);
      continue;
    }
    // Moved aside first: an open elsewhere finds the entry whole or not at all.
    const fs::path stale = root / (".stale-pruned-" + name + "-" + std::to_string(::getpid()));
    fs::rename(entry, stale, e);
    if (!e) fs::remove_all(stale, e);
  }
}

std::string skippedFramesText(const ImportReport& report, const fs::path& source) {
  std::ostringstream text;
  text << report.skipped.size() << " of " << report.frames_found << " frames of " << source.string()
       << " could not be converted and are left out:\n";
  listSkipped(text, report.skipped, 20);
  return text.str();
}

}  // namespace

OpenedSource openSource(const fs::path& path, const ImportOptions& options,
                        const fs::path& cache_root, const ImportProgressCallback& progress) {
  const SourceDetection detection = detectSource(path);
  if (!detection.kind)
    throw Error(path.string(), "", "a sequence, a ROS bag or a dataset folder",
                detection.explanation);
  OpenedSource opened;
  opened.kind = *detection.kind;
  if (opened.kind == SourceKind::Sequence) {
    opened.sequence = loadSequence(path);
    opened.folder = opened.sequence.root;
    return opened;
  }
  opened.converted = true;
  const fs::path root = cache_root.empty() ? defaultImportCacheRoot() : cache_root;
  std::ostringstream key;
  key << std::hex << std::setw(16) << std::setfill('0')
      << fnv1a(conversionFingerprint(path, opened.kind, options));
  // Named after the recording itself: opened through a symbolic link, it is
  // the same entry.
  std::error_code canonical_error;
  fs::path named = fs::weakly_canonical(fs::absolute(path), canonical_error);
  if (canonical_error) named = fs::absolute(path).lexically_normal();
  std::string stem = named.filename().string();
  if (stem.empty()) stem = named.parent_path().filename().string();
  for (char& c : stem)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
  opened.folder = root / (stem + "-" + key.str());
  std::error_code ec;
  if (fs::exists(opened.folder, ec)) {
    if (std::optional<Sequence> cached = readableCacheEntry(opened.folder)) {
      opened.sequence = std::move(*cached);
      opened.reused_cache = true;
      // The folder's time is the entry's last open (pruneImportCache).
      fs::last_write_time(opened.folder, fs::file_time_type::clock::now(), ec);
      if (std::ifstream in(opened.folder / kSkippedFramesFile); in)
        opened.skipped_frames.assign(std::istreambuf_iterator<char>(in), {});
      if (std::ifstream in(opened.folder / kColourLeftOutFile); in)
        opened.colour_left_out.assign(std::istreambuf_iterator<char>(in), {});
      opened.notes = readNotes(opened.folder / kImportNotesFile);
      std::copy_if(opened.notes.begin(), opened.notes.end(), std::back_inserter(opened.warnings),
                   isImportWarning);
      return opened;
    }
    // Moved aside first (an open elsewhere may be reading it), then removed.
    const fs::path stale = root / (".stale-" + key.str() + "-" + std::to_string(::getpid()));
    fs::remove_all(stale, ec);
    fs::rename(opened.folder, stale, ec);
    fs::remove_all(stale, ec);
  }
  fs::create_directories(root, ec);
  if (ec) throw Error(root.string(), "cache", "a folder that can be created", ec.message());
  const fs::path partial =
      root / (".partial-" + key.str() + "-" + std::to_string(::getpid()) + "-" +
              std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
  ImportOptions cache_options = options;
  cache_options.overwrite = false;
  // A problem writing into the cache is the cache's, named as such: the
  // hidden folder it names is gone by the time it is read.
  const auto cacheProblem = [&](const Error& e) {
    const std::string written = e.problem().file;
    const bool inside = written.rfind(partial.string(), 0) == 0;
    return inside ? Error(root.string(), "cache",
                          "a writable import cache with room for the converted recording "
                          "(XDG_CACHE_HOME sets where it is)",
                          e.problem().found + " (writing " +
                              fs::path(written).lexically_relative(partial).string() + ")")
                  : e;
  };
  try {
    opened.report = importSource(opened.kind, path, partial, cache_options, progress);
    if (!opened.report.cancelled) {
      // Inside the folder before it is renamed into place: complete or absent.
      if (!opened.report.skipped.empty()) {
        opened.skipped_frames = skippedFramesText(opened.report, path);
        writeTextFileAtomically(partial / kSkippedFramesFile, opened.skipped_frames);
      }
      opened.colour_left_out = colourLeftOutText(opened.report);
      if (!opened.colour_left_out.empty())
        writeTextFileAtomically(partial / kColourLeftOutFile, opened.colour_left_out);
      opened.notes = notesOneALine(opened.report.notes);
      std::string notes;
      for (const std::string& note : opened.notes) notes += note + "\n";
      writeTextFileAtomically(partial / kImportNotesFile, notes);
      std::copy_if(opened.notes.begin(), opened.notes.end(), std::back_inserter(opened.warnings),
                   isImportWarning);
    }
  } catch (const Error& e) {
    fs::remove_all(partial, ec);
    throw cacheProblem(e);
  } catch (...) {
    fs::remove_all(partial, ec);
    throw;
  }
  if (opened.report.cancelled) {
    fs::remove_all(partial, ec);
    return opened;
  }
  fs::rename(partial, opened.folder, ec);
  if (ec) {  // another process finished the same conversion first
    fs::remove_all(partial, ec);
    if (!isFile(opened.folder / "sequence.json"))
      throw Error(opened.folder.string(), "cache", "a writable cache folder", "rename failed");
  }
  opened.report.output = opened.folder;
  opened.sequence = loadSequence(opened.folder);
  pruneImportCache(root, opened.folder);
  return opened;
}

}  // namespace lom
