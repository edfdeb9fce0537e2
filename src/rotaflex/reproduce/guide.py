"""Report text for a reader who has not read the papers: the introduction and the glossary.

:func:`rotaflex.reproduce.reproduce` passes :func:`introduction` and :data:`GLOSSARY` to
:func:`rotaflex.core.report.write_report`; the report lists only the glossary entries it uses,
and a test checks that every acronym and subscripted symbol in the report text has an entry.
"""

from __future__ import annotations

#: what each reproduce target shows and why it matters, in the order of the report
SECTIONS: dict[str, str] = {
    "rotor": (
        "**Rotor rotation** (Yun & Ren 2008). How a spinning rigid rotor's attitude is described "
        "(Euler angles in several axis sequences, or a quaternion) changes the equations of motion "
        "and where they break down: every three-angle description has a singular attitude, and "
        "truncated (linearised) equations lose energy terms. The section re-derives the paper's "
        "equations, checks its energy figures, and shows where each description is singular. It "
        "matters because a rotor simulation that uses the wrong description stops or drifts "
        "exactly at large tilts. The finite-element rotor-bearing model (critical speeds, "
        "Campbell diagram, unbalance response) is checked here too, against a textbook example."
    ),
    "gear": (
        "**Spur-gear dynamic contact** (Lee & Jang). Two elastic gear teeth meet, share load and "
        "separate; at high speed the teeth can lose contact and rattle. The section re-runs the "
        "paper's cases (speeds, torque ramps) and, because the paper's curves were lost, checks "
        "physics instead: the slow-speed limit must equal the static deflection, energy must "
        "balance, contact constraints must hold. It matters because the dynamic tooth force "
        "(dynamic factor K_v) sets gear life and noise, and a design code (ISO 6336-1) gives only "
        "an estimate of it."
    ),
    "floating": (
        "**Floating flexible bodies** (Kwak & Seong 2005). A spacecraft or robot arm is a body "
        "that moves freely while it vibrates. The paper writes its equations in body-fixed "
        "velocities (quasi-coordinates) and splits them into a rigid-body part and a small "
        "elastic correction (the perturbation method). The section checks the printed equations "
        "term by term against our derivation and then simulates manoeuvres with both the full and "
        "the perturbation equations. It matters because the perturbation method is fast but only "
        "valid for slow manoeuvres; the section shows where it stops being valid."
    ),
    "geared_rotor": (
        "**Geared rotor systems**. A gearbox is shafts, bearings and gears together: the gear mesh "
        "couples the shafts' bending (lateral) motion to their twisting (torsional) motion, so a "
        "mode can move the shafts in their bearings while the teeth deflect. The section builds "
        "two finite-element shafts joined by a gear mesh whose stiffness and transmission error "
        "come from the gear package, draws the Campbell diagram with the mesh modes marked, the "
        "dynamic mesh and bearing forces against speed, and checks the coupled model against its "
        "limits (no mesh: each shaft alone; rigid shafts: the torsional mesh model). It matters "
        "because the bearing forces a mesh excites are what a gearbox designer sizes bearings and "
        "housings for."
    ),
    "sweep": (
        "**Parameter sweeps**. Each domain's example run over a range of one parameter, serially "
        "and in parallel, to show that a study of many cases gives the same numbers as the single "
        "runs and that a finished study is reused, not recomputed. It matters because a design "
        "question (at what speed does the rotor resonate?) is answered by a sweep, not one run."
    ),
}


def introduction(names: list[str]) -> list[str]:
    """Paragraphs of the report's introduction for the reproduce targets ``names``."""
    return [
        "This report re-runs the numerical examples of the papers whose methods rotaflex "
        "implements, draws each figure beside the paper's caption, and measures what the paper "
        "states. Each check is a number we measured and the criterion it must meet; each claim is "
        "a statement of the paper that we measured and report as holding or not. Where the "
        "paper's own curves did not survive, figures are judged by independent checks (closed "
        "forms, conservation laws, a second formulation). Symbols and acronyms are explained in "
        "the glossary at the end.",
        *[SECTIONS[n] for n in names if n in SECTIONS],
    ]


#: term (several spellings separated by " / ") -> meaning, for a reader without the papers
GLOSSARY: dict[str, str] = {
    # general
    "Fig. / eq.": "a figure or an equation of the paper named in the section's title, by its number "
    "there (eq. 27a is equation 27a of that paper)",
    "FE": "finite element: a structure divided into small elements whose stiffness and mass "
    "matrices are assembled into a model with many degrees of freedom",
    "EOM": "equations of motion",
    "RK4": "the classical fourth-order Runge-Kutta time-stepping method",
    "RMS": "root mean square",
    "CPU": "central processing unit; CPU time is the processor time a run used, which on a "
    "shared machine tells its cost better than the elapsed (wall) time",
    "OCR": "optical character recognition: our copies of the papers are scans read by OCR, so some "
    "printed symbols or signs are uncertain",
    "MN": "meganewton (1e6 N); 1 MN/m is a bearing stiffness of 1e6 N/m",
    "NASA / TM": "NASA Technical Memorandum (TM-105326 is a gear-dynamics report the gear paper compares with)",
    "DIR": "the output directory given with --out",
    "ROSS": "an open-source rotordynamics program whose documented results for the same example we compare with",
    # rotor rotation
    "K_123 / K_313 / K_q": "kinetic energy of the rotor computed from the inertial-frame angular "
    "velocity, with the 1-2-3 or 3-1-3 Euler-angle sequence or the quaternion",
    "K*_123 / K*_q": "the same kinetic energy computed from the body-frame angular velocity (the "
    "star marks the body frame); computed consistently both give the same energy, and the paper's "
    "figures compare the two computations",
    "J_313": "the inertia matrix the paper prints for the 3-1-3 sequence",
    "M_q": "mass matrix of the quaternion (spherical-coordinate) equations of motion; where it "
    "vanishes the equations are singular",
    "1-2-3 / 3-1-3": "Euler-angle sequences: the axes of the three successive rotations",
    "Omega": "spin speed of the rotor [rad/s]",
    # FE rotor
    "MAC": "modal assurance criterion: the squared normalised inner product of two mode shapes, 1 "
    "for the same shape and 0 for orthogonal ones; used to follow a mode from speed to speed",
    "AF / SM": "amplification factor (peak response over the half-power bandwidth, AF = N_c / "
    "(N_2 - N_1)) and separation margin (distance of a critical speed from the operating speed, "
    "SM = |N_op - N_c| / N_op), as in API 684",
    "API": "American Petroleum Institute; its rotordynamics standard defines AF and SM",
    "N_c / N_1 / N_2 / N_op": "critical speed (response peak), the speeds where the response is "
    "1/sqrt(2) of the peak below and above it, and the operating speed [rpm]",
    "UCS": "undamped critical speed map: critical speeds against bearing stiffness",
    "1X": "excitation once per revolution (unbalance)",
    # gear
    "DTE": "dynamic transmission error: the angle by which the driven gear lags where rigid teeth "
    "would put it, in a run, as a length along the line of action",
    "TE / STE": "transmission error, and static (loaded, slow-speed) transmission error",
    "K_v": "dynamic factor: peak dynamic tooth force over the static tooth force (ISO 6336-1)",
    "ISO": "International Organization for Standardization; ISO 6336-1 rates gear load capacity "
    "(mesh stiffness c' and c_gamma, dynamic factor K_v), ISO 21771 defines gear geometry",
    "c_gamma": "ISO 6336-1 mean mesh stiffness per unit face width [N/(mm um)]",
    "n_E1": "ISO 6336-1 resonance speed of the pinion [rpm]",
    "f_n": "a natural frequency [Hz]",
    "r_b": "base-circle radius of a gear [m]; r_b times a rotation angle is a length along the line of action",
    "k_s": "lateral stiffness of the shaft between its bearings [N/m] (Jeffcott rotor)",
    "k_pair": "stiffness of one tooth pair in contact [N/m]",
    "HHT / HHT-alpha": "the Hilber-Hughes-Taylor alpha method: an implicit time integrator that "
    "damps high frequencies, allowing large time steps",
    "Craig-Bampton": "a model reduction that keeps a structure's interface degrees of freedom plus a "
    "few fixed-interface vibration modes",
    "QS": "quasi-static: the slow-speed limit, where inertia is negligible",
    "E_kin / E_strain / W_ext / E_0": "kinetic energy, strain energy, work of the external torques, "
    "and the initial energy, in the energy-balance check",
    # floating
    "EI": "bending stiffness of a beam section, Young's modulus times second moment of area [N m^2]",
    "V_x0 / V_y0 / V_x1": "body-frame velocity components of the floating frame: subscript 0 the "
    "rigid (zero-order) part, 1 the first-order correction of the perturbation method",
    "R_x / R_y": "inertial position of the floating frame's origin",
    "K_b / M_b": "the elastic stiffness and mass matrices of the beam's modes",
    "Q_1": "the first-order generalised (modal) force",
    "d_3": "the rigid-manoeuvre forcing term of the paper's eq. 28b/41",
    "phibar / phibar_b": "modal integrals of the mode shapes (the paper's coupling terms between "
    "rigid motion and vibration)",
}
