"""Figures, animations, the viewer and terminal progress: everything drawn from results, none of it physics."""
