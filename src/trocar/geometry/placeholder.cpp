// Placeholder so the target has a source until the geometry kernels land; delete then.
