#include "trocar/collision/contact.h"

namespace trocar {

const char* role_name(ObjectRole role) {
  switch (role) {
    case ObjectRole::kInstrument: return "instrument";
    case ObjectRole::kTissue: return "tissue";
    case ObjectRole::kRigid: return "rigid";
  }
  return "unknown";
}

const char* contact_kind_name(ContactKind kind) {
  switch (kind) {
    case ContactKind::kInstrumentTissue: return "instrument-tissue";
    case ContactKind::kInstrumentInstrument: return "instrument-instrument";
    case ContactKind::kInstrumentRigid: return "instrument-rigid";
    case ContactKind::kTissueRigid: return "tissue-rigid";
    case ContactKind::kTissueTissue: return "tissue-tissue";
  }
  return "unknown";
}

ContactKind contact_kind(ObjectRole a, ObjectRole b) {
  if (a == ObjectRole::kInstrument) {
    if (b == ObjectRole::kInstrument) return ContactKind::kInstrumentInstrument;
    if (b == ObjectRole::kTissue) return ContactKind::kInstrumentTissue;
    return ContactKind::kInstrumentRigid;
  }
  if (a == ObjectRole::kTissue && b == ObjectRole::kTissue) return ContactKind::kTissueTissue;
  // tissue–rigid (rigid–rigid is never tested).
  return ContactKind::kTissueRigid;
}

}  // namespace trocar
