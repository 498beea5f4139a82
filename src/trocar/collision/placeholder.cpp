// Placeholder so the target has a source until the collision module lands; delete then.
