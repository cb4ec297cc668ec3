"""First-party kinds, registered through the same hooks as any plugin (DESIGN rule 1)."""
