"""section (placeholder until filled in)."""
