// SPDX-License-Identifier: MIT
#include "TimelinePanel.h"

#include <QHBoxLayout>
#include <QLabel>
#include <QLocale>
#include <QSlider>
#include <QTimer>
#include <QToolButton>

#include "Timeline.h"

namespace bsdeform {

TimelinePanel::TimelinePanel(Timeline& timeline, std::function<double()> speed, QWidget* parent)
    : QWidget(parent), m_timeline(timeline), m_speed(std::move(speed)) {
  m_replay = new QToolButton;
  m_replay->setText(tr("Replay"));
  m_replay->setCheckable(true);
  m_replay->setToolTip(tr("Play the kept states forward from the slider's position at the clock's speed, "
                          "without simulating"));
  m_slider = new QSlider(Qt::Horizontal);
  m_slider->setObjectName(QStringLiteral("timelineSlider"));
  m_slider->setFocusPolicy(Qt::NoFocus);  // the arrow keys stay with the 3D view
  m_label = new QLabel;
  m_label->setMinimumWidth(m_label->fontMetrics().horizontalAdvance(QStringLiteral("t = 00000.000 s of 00000.000 s · 000000 states")));
  auto* row = new QHBoxLayout(this);
  row->setContentsMargins(4, 2, 4, 2);
  row->addWidget(m_replay);
  row->addWidget(m_slider, 1);
  row->addWidget(m_label);
  m_timer = new QTimer(this);
  m_timer->setInterval(16);
  connect(m_timer, &QTimer::timeout, this, &TimelinePanel::tick);
  connect(m_replay, &QToolButton::toggled, this, &TimelinePanel::setReplaying);
  connect(m_slider, &QSlider::valueChanged, this, [this](int index) {
    if (!m_refreshing && index != m_timeline.position()) m_timeline.showFrame(index);
  });
  connect(&m_timeline, &Timeline::changed, this, &TimelinePanel::refresh);
  refresh();
}

QString TimelinePanel::label() const {
  const StateHistory& h = m_timeline.history();
  if (h.isEmpty()) return tr("no states kept");
  const QString times = tr("t = %1 s of %2 s")
                            .arg(QLocale().toString(h[m_timeline.position()].time, 'g', 6),
                                 QLocale().toString(h.back().time, 'g', 6));
  return times + (h.size() == 1 ? tr(" · 1 state") : tr(" · %1 states").arg(h.size()));
}

QString TimelinePanel::memoryText() const {
  const StateHistory& h = m_timeline.history();
  const QLocale locale;
  QString text = tr("States kept: %1, %2 of the %3 budget")
                     .arg(h.size())
                     .arg(locale.formattedDataSize(qint64(h.bytes())), locale.formattedDataSize(qint64(h.budget())));
  text += h.thinnings() ? tr("; thinned %1 times so far: older states are sparser").arg(h.thinnings())
                        : tr("; when full, every second state of the older half is dropped");
  return text;
}

bool TimelinePanel::isReplaying() const { return m_timer->isActive(); }

void TimelinePanel::setReplaying(bool on) {
  if (on == isReplaying()) return;
  if (on) {
    if (m_timeline.isAtEnd()) m_timeline.showFrame(0);
    m_wall.start();
    m_timer->start();
  } else {
    m_timer->stop();
  }
  if (m_replay->isChecked() != on) m_replay->setChecked(on);
}

void TimelinePanel::tick() {
  const double seconds = m_wall.restart() / 1000.0;
  if (!m_timeline.advanceReplay(seconds * m_speed())) setReplaying(false);
}

void TimelinePanel::refresh() {
  m_refreshing = true;
  const StateHistory& h = m_timeline.history();
  m_slider->setRange(0, std::max(0, h.size() - 1));
  m_slider->setValue(std::max(0, m_timeline.position()));
  m_refreshing = false;
  m_label->setText(label());
  const QString tip = tr("Scrub through the states shown so far (the simulation pauses there); "
                         "stepping on from an earlier state discards the later ones (Edit > Undo brings them back).\n") +
                      memoryText();
  m_slider->setToolTip(tip);
  m_label->setToolTip(tip);
}

}  // namespace bsdeform
