"""mixed (placeholder until filled in)."""
