"""Fluid-film journal bearings for the FE rotor: plain cylindrical bearing, short and finite-length models."""

from rotaflex.rotor.fe.bearings.fluid_film import (
    FluidFilm,
    FluidFilmTable,
    coefficients_from_reaction,
    fluid_film_table,
)

__all__ = ["FluidFilm", "FluidFilmTable", "coefficients_from_reaction", "fluid_film_table"]
