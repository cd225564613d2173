"""mechanism (placeholder until filled in)."""
