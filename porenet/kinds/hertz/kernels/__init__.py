"""The Hertzian solid (docs/model.md section 5): contact laws, loads, the chain solver and the
sparse direct solver."""
