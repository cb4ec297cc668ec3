"""First-party kinds, registered through the hooks any plugin uses.

Built-ins are plugins too (docs/architecture.md, rule 1).
"""
