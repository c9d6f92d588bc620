#include "lom/ui/about_reaction.hpp"

#include <QMessageBox>

namespace lom::ui {

QString studioVersion() { return QStringLiteral(LOM_VERSION); }

AboutReaction::AboutReaction(QAction* action, QWidget* dialog_parent)
    : Reaction(action), dialog_parent_(dialog_parent) {}

void AboutReaction::onTriggered() {
  QMessageBox::about(dialog_parent_, tr("About LabelOctoMap Studio"),
                     tr("<h3>LabelOctoMap Studio %1</h3>"
                        "<p>Turns recorded RGB-D frames with per-pixel label probabilities into "
                        "labelled 3D maps (LabelOctoMap, IROS 2017).</p>"
                        "<p>Built with Qt %2 and VTK.</p>")
                         .arg(studioVersion(), QString::fromLatin1(qVersion())));
}

}  // namespace lom::ui
