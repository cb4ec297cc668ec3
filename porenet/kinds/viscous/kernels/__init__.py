"""The viscous drainage model (docs/model.md section 4): the menisci, the pressure diffusion, the
explicit, RKC (with local time steps) and implicit integrators."""
