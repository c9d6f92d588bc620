#include "lom/ui/export_map_reaction.hpp"

#include <QAction>
#include <QEventLoop>
#include <QFileInfo>
#include <QPointer>
#include <set>

#include "lom/ui/map_worker.hpp"
#include "lom/ui/save_file_dialog.hpp"
#include "lom/ui/sequence_controller.hpp"
#include "lom/ui/studio_session.hpp"

namespace lom::ui {

ExportMapReaction::ExportMapReaction(QAction* action, ExportOptions options,
                                     StudioSession& session, QWidget* parent,
                                     const ErrorReporter& report)
    : Reaction(action), options_(std::move(options)), session_(session), parent_(parent),
      report_(report) {
  auto update = [this] {
    const auto snapshot = session_.worker().snapshot();
    this->action()->setEnabled(snapshot && !snapshot->empty());
  };
  connect(&session_.worker(), &MapWorker::snapshotChanged, this, update);
  update();
  connect(this, &ExportMapReaction::finished, this, [this](const QString& message, bool ok) {
    if (!ok) report_(tr("Export"), message);
  });
}

QString ExportMapReaction::askPath() const {
  const QString extension = QString::fromLatin1(exportFormatName(options_.format));
  // Beside the sequence (where Open Map starts) and named after it: another
  // sequence's map is not proposed for replacing. A colour octree gets a name
  // of its own, since it may not replace the map saved as NAME.ot.
  const QString suffix =
      (options_.format == ExportFormat::Ot && !options_.native ? "-colour." : ".") + extension;
  QString start = session_.controller().proposedOutput(suffix);
  if (start.isEmpty()) start = "map" + suffix;
  return askSaveFileName(parent_, options_.native ? tr("Save Map") : tr("Export Map"), start,
                         tr("%1 files (*.%2)").arg(extension.toUpper(), extension), {extension});
}

void ExportMapReaction::onTriggered() {
  const QString path = askPath();
  if (!path.isEmpty()) exportTo(path);
}

bool ExportMapReaction::exportAndWait() {
  const QString path = askPath();
  return !path.isEmpty() && exportToAndWait(path);
}

bool ExportMapReaction::exportToAndWait(const QString& path) {
  bool done = false, written = false;
  QEventLoop loop;
  const auto connection =
      connect(this, &ExportMapReaction::finished, &loop, [&](const QString&, bool ok) {
        done = true;
        written = ok;
        loop.quit();
      });
  // `finished` comes once the export is off the worker's list of work, so a
  // window closing after Save Map… does not ask to stop an export that is over.
  if (exportTo(path) && !done) loop.exec();
  disconnect(connection);
  return written;
}

bool ExportMapReaction::exportTo(const QString& path) {
  if (const QString input = session_.controller().sequenceFileAt(path); !input.isEmpty()) {
    report_(tr("Export"), tr("%1 is a file of the sequence (%2): exports never replace it. "
                             "Choose another name.")
                              .arg(path, input));
    return false;
  }
  QPointer<ExportMapReaction> self(this);
  MapWorker* worker = &session_.worker();
  ExportOptions options = options_;
  QString shown_note;
  const std::set<int>& hidden = session_.hiddenLabels();
  if (only_shown_ && only_shown_->isChecked() && !hidden.empty() && session_.sequence()) {
    std::set<int> shown;
    const int count = static_cast<int>(session_.sequence()->labels.size());
    for (int label = 0; label < count; ++label)
      if (!hidden.count(label)) shown.insert(label);
    options.labels = shown;
    shown_note = tr(" (labels shown in the 3D view only: %1 hidden)").arg(hidden.size());
  }
  // The map's own tree, every label, is the map saved (Open Map reads it
  // back); a colour octree, other formats and a part of the labels are not.
  const bool saves_map = options.format == ExportFormat::Ot && options.native && !options.labels;
  if (!saves_map && LabelMap::isMapFile(path.toStdString())) {
    const QString loss =
        options.native ? tr("this map's shown labels only, and the voxels of the others would be "
                            "lost")
                       : tr("a colour octree, and its label probabilities would be lost (Open Map "
                            "could not read it back)");
    report_(tr("Export"), tr("%1 holds a labelled map (the map opened or saved, or another): this "
                             "export would replace it with %2. Choose another name, or use File ▸ "
                             "Save Map… to replace it with this whole map.")
                              .arg(path, loss));
    return false;
  }
  if (worker->isFusing())
    emit queued(tr("Export to %1 queued: it runs when fusion finishes (Fusion ▸ Cancel Fusion "
                   "ends it now).")
                    .arg(QFileInfo(path).fileName()));
  // Cancel Fusion ends the wait and exports the map fused so far; a re-fusion
  // or another sequence replaces the map the export was asked for.
  const unsigned generation = worker->mapGeneration();
  const bool behind_fusion = worker->isFusing();
  worker->withMapThen(
      [self, worker, options, path, generation, behind_fusion, shown_note,
       saves_map](const LabelMap* map) {
        QString message;
        bool ok = false;
        if (behind_fusion && worker->mapGeneration() != generation) {
          message = tr("Export to %1 dropped: the map it waited for was replaced (fused again, or "
                       "another sequence opened) before its fusion finished. Export again.")
                        .arg(path);
        } else if (!map) {
          message = tr("Fuse the sequence first.");
        } else {
          try {
            const ExportSummary summary = exportMap(*map, options, path.toStdString());
            message = tr("Wrote %1 %2 to %3")
                          .arg(summary.items)
                          .arg(QString::fromStdString(summary.item_name), path) +
                      shown_note;
            ok = true;
          } catch (const std::exception& error) {
            message = QString::fromStdString(error.what());
          }
        }
        const bool saved = ok && saves_map;
        return std::function<void()>([self, worker, message, ok, saved, generation] {
          if (saved) worker->markMapSaved(generation);
          if (self) emit self->finished(message, ok);
        });
      },
      tr("export of the map to %1").arg(path));
  return true;
}

}  // namespace lom::ui
