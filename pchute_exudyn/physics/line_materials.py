"""Line materials: normalised load-elongation curves of braided cords and webbing (``docs/models/line_materials.md``).

A case line may name a material and its rated breaking strength T_b instead of a stiffness or a table::

    material = "kevlar"
    breaking_strength = 12000.0      # N: the whole line (all its legs or plies together)

and the reader turns it into the line's load-elongation table, T_table(eps) = T_b f(eps), with f the material's
curve below (T / T_b against strain, from (0, 0) to (eps_b, 1)). Every method then uses the table as any other.

The curves are for the *cord or webbing*, not the fibre. A braided cord stretches more than its fibre before it
breaks (the braid's helix straightens and its crimp is taken up) and is softer at first: the aramid curves are a
quadratic toe joined with a continuous slope to a straight line whose slope is the fibre's, T_b / eps_fibre (the fibre
taken linear to break), the toe's length set by the assumed structural stretch s (the cord breaks at
eps_b = eps_fibre + s, the toe ends at 2 s). Sources and assumptions: ``docs/models/line_materials.md``.
"""

from __future__ import annotations

from dataclasses import dataclass

from .lines import LoadElongation


@dataclass(frozen=True)
class LineMaterial:
    """A material's normalised load-elongation curve.

    Attributes
    ----------
    name : str
        The case's name of the material (``material = "<name>"``).
    description : str
        What the curve stands for (fibre and construction).
    strain : tuple of float
        Strain eps = (L - L0) / L0 (-) of each point, from 0 to the breaking strain.
    fraction : tuple of float
        T / T_b (-) at each strain, from 0 to 1 (the line breaks at the last point).
    source : str
        Where the fibre's data come from and what is assumed.
    """

    name: str
    description: str
    strain: tuple
    fraction: tuple
    source: str

    @property
    def breaking_strain(self) -> float:
        """eps_b (-): the strain at which the line breaks, the curve's last point."""
        return self.strain[-1]

    def table(self, breaking_strength: float) -> LoadElongation:
        """The load-elongation table of a line of this material rated at ``breaking_strength`` T_b (N)."""
        return LoadElongation(self.strain, tuple(breaking_strength * f for f in self.fraction))


@dataclass(frozen=True)
class RatedLine:
    """A line made of ``material`` with the rated ``breaking_strength`` T_b (N, the whole line)."""

    material: LineMaterial
    breaking_strength: float

    @property
    def breaking_strain(self) -> float:
        """eps_b (-) of the line's material."""
        return self.material.breaking_strain

    def table(self) -> LoadElongation:
        """T_table(eps) = T_b f(eps) (``LineMaterial.table``)."""
        return self.material.table(self.breaking_strength)


def toe_and_line(fibre_strain: float, structural: float, strains: tuple) -> tuple:
    """T / T_b of a braided cord at ``strains``: the quadratic toe eps^2 / (4 s eps_f) up to 2 s, then the line
    (eps - s) / eps_f, with eps_f the fibre's breaking strain and s the structural stretch (continuous in value and
    slope at 2 s; 1 at eps_b = eps_f + s). The aramid records below hold these values rounded to 4 digits."""
    return tuple(e * e / (4.0 * structural * fibre_strain) if e <= 2.0 * structural
                 else (e - structural) / fibre_strain for e in strains)


KEVLAR = LineMaterial(
    "kevlar", "Kevlar 29 (para-aramid) braided cord",
    strain=(0.0, 0.005, 0.01, 0.018, 0.03, 0.045),
    fraction=(0.0, 0.0193, 0.0772, 0.25, 0.5833, 1.0),
    source="fibre: DuPont, Kevlar aramid fiber technical guide (Kevlar 29: modulus about 70.5 GPa, elongation at "
           "break about 3.6 %, quoted); the cord's structural stretch of 0.9 % (break at 4.5 %) and the toe assumed")
TECHNORA = LineMaterial(
    "technora", "Technora T-200 class (co-para-aramid) braided cord",
    strain=(0.0, 0.005, 0.01, 0.018, 0.03, 0.04, 0.054),
    fraction=(0.0, 0.0154, 0.0617, 0.2, 0.4667, 0.6889, 1.0),
    source="fibre: Teijin, Technora tensile properties (modulus 530 cN/dtex, about 74 GPa at 1.39 g/cm3; "
           "elongation at break 4.5 %, read); the cord's structural stretch of 0.9 % (break at 5.4 %) and the toe "
           "assumed")
NYLON = LineMaterial(
    "nylon", "nylon 6,6 webbing or braided cord",
    strain=(0.0, 0.02, 0.05, 0.1, 0.15, 0.2),
    fraction=(0.0, 0.0316, 0.125, 0.3536, 0.6495, 1.0),
    source="elongation at break: nylon 6,6 fibre 20 % (Teijin's comparison table, read), parachute webbing and cord "
           "specified at 20-25 % (U.S. Navy aircrew survival equipmentman manual, read); break at 20 % and the "
           "stiffening shape (T / T_b = (eps / eps_b)^1.5) assumed")

LINE_MATERIALS = {material.name: material for material in (KEVLAR, TECHNORA, NYLON)}
"""Every line material a case can name, by name."""
