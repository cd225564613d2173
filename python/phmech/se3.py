"""SE(3) algebra (placeholder until filled in)."""
