"""timoshenko (placeholder until filled in)."""
