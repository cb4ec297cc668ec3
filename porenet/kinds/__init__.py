"""porenet's own kinds, one folder each, shaped like a plugin package (docs/architecture.md).

Each folder holds its config (``config.py``), its model (``model.py``), its kernels
(``kernels/``), its cost estimate (``cost.py``), its compile warm-ups (``warmups.py``), its
registration (``plugin.py``, the hooks any plugin implements), its page (``README.md``) and its
tests. The core imports none of them: :data:`porenet.hooks.DEFAULT_PLUGINS` names their
``plugin`` modules, and everything else is asked of the kind through the registry.
"""
