"""Every derivation result as the UI shows it (GENERATED FILE, do not edit).

Written by ``python -m derivations.codegen`` from ``derivations/registry.py``;
``python -m derivations.codegen --check`` and the test suite fail when it is stale. The window
and the lesson loader read the derivations from here (``explorer.derived``), so
they never import sympy. Each entry: name -> (LaTeX, statement, value), value the
number (or the number a formula equals) as a float, or None.
"""

RESULTS: dict[str, tuple[str, str, float | None]] = {
    'solid_angles.front_face': (
        '\\Delta\\omega_{\\mathrm{front}} = 4 \\operatorname{atan}{\\left(\\frac{\\sqrt{11}}{33} '
        '\\right)}',
        "Solid angle of a neighbour's far face seen from the source cell centre.",
        0.4006696846462392,
    ),
    'solid_angles.side_face': (
        '\\Delta\\omega_{\\mathrm{side}} = - \\frac{\\pi}{3} + 2 '
        '\\operatorname{atan}{\\left(\\frac{3 \\sqrt{11}}{11} \\right)}',
        "Solid angle of one of a neighbour's four side faces seen from the source cell centre.",
        0.42343135443673907,
    ),
    'solid_angles.front_face_spherical': (
        '\\Delta\\omega_{\\mathrm{front}} = - 2 \\pi + 2 \\operatorname{acos}{\\left(- '
        '\\frac{1}{10} \\right)} + 4 \\operatorname{acos}{\\left(\\frac{3 \\sqrt{5}}{10} '
        '\\right)}',
        "Front face as two spherical triangles (Girard's excess); equals front_face.",
        0.4006696846462392,
    ),
    'solid_angles.side_face_spherical': (
        '\\Delta\\omega_{\\mathrm{side}} = - \\frac{4 \\pi}{3} + '
        '\\operatorname{acos}{\\left(\\frac{7 \\sqrt{15}}{30} \\right)} + '
        '\\operatorname{acos}{\\left(- \\frac{\\sqrt{3}}{6} \\right)} + '
        '\\operatorname{acos}{\\left(- \\frac{3 \\sqrt{5}}{10} \\right)}',
        "Side face as two spherical triangles (Girard's excess); equals side_face.",
        0.42343135443673907,
    ),
    'solid_angles.tiling': (
        '6 \\left(- \\frac{4 \\pi}{3} + 4 \\operatorname{atan}{\\left(\\frac{\\sqrt{11}}{33} '
        '\\right)} + 8 \\operatorname{atan}{\\left(\\frac{3 \\sqrt{11}}{11} \\right)}\\right) = '
        '4 \\pi',
        'The 6 front faces and 24 side faces of the neighbours cover the sphere exactly once '
        '(front + 4 side = 2π/3).',
        12.566370614359172,
    ),
    'solid_angles.cube_face': (
        '\\Delta\\omega_{\\mathrm{cube\\ face}} = \\frac{2 \\pi}{3}',
        'One cube face seen from the cube centre: the whole field of a 90° square frustum (4π/6).',
        2.0943951023931957,
    ),
    'solid_angles.sphere': (
        '\\int_{S^2} d\\omega = 4 \\pi',
        'Solid angle of the whole sphere: the integral of dω over all directions.',
        12.566370614359172,
    ),
    'solid_angles.projected_hemisphere': (
        '\\int_{H^2} \\cos\\theta \\, d\\omega = \\pi',
        'Projected solid angle of the hemisphere: the integral of cos θ dω over it, π.',
        3.141592653589793,
    ),
    'sh.c0': (
        'c_{0} = \\frac{1}{2 \\sqrt{\\pi}}',
        'Band-0 SH constant: the band-0 basis function is 1/(2√π) everywhere.',
        0.28209479177387814,
    ),
    'sh.c1': (
        'c_{1} = \\frac{\\sqrt{3}}{2 \\sqrt{\\pi}}',
        'Band-1 SH constant: Y1m = ±√3/(2√π)·(y, z, x).',
        0.4886025119029199,
    ),
    'sh.basis_l1': (
        'Y(x, y, z) = \\left[\\begin{matrix}\\frac{1}{2 \\sqrt{\\pi}}\\\\- \\frac{\\sqrt{3} y}{2 '
        '\\sqrt{\\pi}}\\\\\\frac{\\sqrt{3} z}{2 \\sqrt{\\pi}}\\\\- \\frac{\\sqrt{3} x}{2 '
        '\\sqrt{\\pi}}\\end{matrix}\\right]',
        "L1 real SH basis in the annotations' order and signs.",
        None,
    ),
    'sh.coslobe_c0': (
        '\\mathrm{lobe}_{0}(+z) = \\frac{\\sqrt{\\pi}}{2}',
        'Band-0 coefficient of the clamped cosine lobe: the integral of cos θ times the band-0 '
        'basis function dω over the hemisphere.',
        0.886226925452758,
    ),
    'sh.coslobe_c1': (
        '\\mathrm{lobe}_{2}(+z) = \\frac{\\sqrt{3} \\sqrt{\\pi}}{3}',
        'Band-1 coefficient of the clamped cosine lobe around z: the integral of cos θ · Y10 dω '
        'over the hemisphere.',
        1.0233267079464885,
    ),
    'sh.net_flux_c1': (
        '\\mathrm{flux}_{2}(+z) = \\frac{2 \\sqrt{3} \\sqrt{\\pi}}{3}',
        "Band-1 coefficient of ⟨e_z, ω⟩ (the light vector's kernel): the integral of z · Y10 dω "
        'over the sphere, √(4π/3) = 2·SH_COSLOBE_C1; every other L2 coefficient is 0.',
        2.046653415892977,
    ),
    'sh.lobe': (
        '\\mathrm{lobe}(n) = \\left[\\begin{matrix}\\frac{\\sqrt{\\pi}}{2}\\\\- \\frac{\\sqrt{3} '
        '\\sqrt{\\pi} n_{y}}{3}\\\\\\frac{\\sqrt{3} \\sqrt{\\pi} n_{z}}{3}\\\\- \\frac{\\sqrt{3} '
        '\\sqrt{\\pi} n_{x}}{3}\\end{matrix}\\right]',
        'SH projection of max(0, ⟨n, ω⟩) around a unit normal n: linear in n.',
        None,
    ),
    'sh.flux_factor': (
        '\\Phi / f_{0} = 2 \\sqrt{\\pi}',
        'Flux of an intensity SH vector f: ∫ f·Y dω = 2√π·f0.',
        3.544907701811032,
    ),
    'sh.clamped_cosine_energy': (
        '\\int \\max(\\cos\\theta, 0)^{2} \\, d\\omega = \\frac{2 \\pi}{3}',
        'Energy of the clamped cosine: ∫ max(0, cos θ)² dω = 2π/3.',
        2.0943951023931957,
    ),
    'sh.l1_energy_fraction': (
        'E_{L1} / E = \\frac{7}{8}',
        "Share of the clamped cosine's energy kept by its L1 (4-coefficient) projection.",
        0.875,
    ),
    'sh.l2_energy_fraction': (
        'E_{L2} / E = \\frac{127}{128}',
        "Share of the clamped cosine's energy kept by its L2 (9-coefficient) projection.",
        0.9921875,
    ),
    'sh.band0_energy_fraction': (
        'E_{0} / E = \\frac{3}{8}',
        "Share of the clamped cosine's energy in SH band 0 alone.",
        0.375,
    ),
    'sh.band1_energy_fraction': (
        'E_{1} / E = \\frac{1}{2}',
        "Share of the clamped cosine's energy in SH band 1 alone.",
        0.5,
    ),
    'sh.band2_energy_fraction': (
        'E_{2} / E = \\frac{15}{128}',
        "Share of the clamped cosine's energy in SH band 2 alone.",
        0.1171875,
    ),
    'sh.basis_l2': (
        'Y_{L2}(x, y, z) = \\left[\\begin{matrix}\\frac{1}{2 \\sqrt{\\pi}}\\\\- \\frac{\\sqrt{3} '
        'y}{2 \\sqrt{\\pi}}\\\\\\frac{\\sqrt{3} z}{2 \\sqrt{\\pi}}\\\\- \\frac{\\sqrt{3} x}{2 '
        '\\sqrt{\\pi}}\\\\\\frac{\\sqrt{15} x y}{2 \\sqrt{\\pi}}\\\\- \\frac{\\sqrt{15} y z}{2 '
        '\\sqrt{\\pi}}\\\\\\frac{\\sqrt{5} \\left(3 z^{2} - 1\\right)}{4 \\sqrt{\\pi}}\\\\- '
        '\\frac{\\sqrt{15} x z}{2 \\sqrt{\\pi}}\\\\\\frac{\\sqrt{15} \\left(x^{2} - '
        'y^{2}\\right)}{4 \\sqrt{\\pi}}\\end{matrix}\\right]',
        'L2 (9-coefficient) real SH basis, same convention.',
        None,
    ),
    'sh.l2_c0': (
        'c_{0} = \\frac{1}{2 \\sqrt{\\pi}}',
        'L2 basis: Y00 constant.',
        0.28209479177387814,
    ),
    'sh.l2_c1': (
        'c_{1} = \\frac{\\sqrt{3}}{2 \\sqrt{\\pi}}',
        'L2 basis: band-1 constant.',
        0.4886025119029199,
    ),
    'sh.l2_c2': (
        'c_{2} = \\frac{\\sqrt{15}}{2 \\sqrt{\\pi}}',
        'L2 basis: constant of xy, yz, xz (√15/(2√π)).',
        1.0925484305920792,
    ),
    'sh.l2_c3': (
        'c_{3} = \\frac{\\sqrt{5}}{4 \\sqrt{\\pi}}',
        'L2 basis: constant of 3z²−1 (√5/(4√π)).',
        0.31539156525252,
    ),
    'sh.l2_c4': (
        'c_{4} = \\frac{\\sqrt{15}}{4 \\sqrt{\\pi}}',
        'L2 basis: constant of x²−y² (√15/(4√π)).',
        0.5462742152960396,
    ),
    'sh.l2_coslobe_c0': (
        '\\mathrm{lobe}_{0}(+z) = \\frac{\\sqrt{\\pi}}{2}',
        'Clamped cosine lobe, band 0 (L2 basis).',
        0.886226925452758,
    ),
    'sh.l2_coslobe_c1': (
        '\\mathrm{lobe}_{2}(+z) = \\frac{\\sqrt{3} \\sqrt{\\pi}}{3}',
        'Clamped cosine lobe, band 1 (L2 basis).',
        1.0233267079464885,
    ),
    'sh.l2_coslobe_c2': (
        '\\mathrm{lobe}_{6}(+z) = \\frac{\\sqrt{5} \\sqrt{\\pi}}{8}',
        'Clamped cosine lobe around z, band 2: the integral of cos θ · Y20 dω over the '
        'hemisphere, √(5π)/8.',
        0.4954159122007514,
    ),
    'sh.zonal_rotation_factors': (
        '(A_{0}, A_{1}, A_{2}) = \\left[\\begin{matrix}\\pi\\\\\\frac{2 '
        '\\pi}{3}\\\\\\frac{\\pi}{4}\\end{matrix}\\right]',
        'Clamped cosine, band factors A_l (l = 0, 1, 2) of lobe_k(n) = A_l·Y_k(n).',
        None,
    ),
    'sh.lobe_l2': (
        '\\mathrm{lobe}_{L2}(n) = \\left[\\begin{matrix}\\frac{\\sqrt{\\pi}}{2}\\\\- '
        '\\frac{\\sqrt{3} \\sqrt{\\pi} n_{y}}{3}\\\\\\frac{\\sqrt{3} \\sqrt{\\pi} n_{z}}{3}\\\\- '
        '\\frac{\\sqrt{3} \\sqrt{\\pi} n_{x}}{3}\\\\\\frac{\\sqrt{15} \\sqrt{\\pi} n_{x} '
        'n_{y}}{8}\\\\- \\frac{\\sqrt{15} \\sqrt{\\pi} n_{y} n_{z}}{8}\\\\\\frac{3 \\sqrt{5} '
        '\\sqrt{\\pi} n_{z}^{2}}{16} - \\frac{\\sqrt{5} \\sqrt{\\pi}}{16}\\\\- \\frac{\\sqrt{15} '
        '\\sqrt{\\pi} n_{x} n_{z}}{8}\\\\\\frac{\\sqrt{15} \\sqrt{\\pi} n_{x}^{2}}{16} - '
        '\\frac{\\sqrt{15} \\sqrt{\\pi} n_{y}^{2}}{16}\\end{matrix}\\right]',
        'L2 projection of max(0, ⟨n, ω⟩) around a unit normal n (9 coefficients); the first four '
        'are the L1 lobe.',
        None,
    ),
    'sh.l2_lobe_c2': (
        'k_{xy} = \\frac{\\sqrt{15} \\sqrt{\\pi}}{8}',
        'L2 lobe around n, coefficient of n_x·n_y in band 2 (m = −2): π/4·√15/(2√π).',
        0.8580855308097834,
    ),
    'sh.l2_lobe_c3': (
        'k_{3z^{2}-1} = \\frac{\\sqrt{5} \\sqrt{\\pi}}{16}',
        'L2 lobe around n, m = 0 term: SH_L2_LOBE_C3·(3n_z² − 1), π/4·√5/(4√π).',
        0.2477079561003757,
    ),
    'sh.l2_lobe_c4': (
        'k_{x^{2}-y^{2}} = \\frac{\\sqrt{15} \\sqrt{\\pi}}{16}',
        'L2 lobe around n, coefficient of n_x² − n_y² (m = 2): π/4·√15/(4√π).',
        0.4290427654048917,
    ),
    'rsm.irradiance': (
        'E = \\frac{\\Phi_{L}}{4 \\pi r^{2}}',
        'Irradiance on a surfel facing a point light of flux Φ_L at distance r.',
        None,
    ),
    'rsm.outgoing_radiance': (
        'L_{o} = \\frac{\\Phi_{L} c_{\\mathrm{diff}} \\max\\left(0, \\cos{\\left(\\theta_{i} '
        '\\right)}\\right)}{4 \\pi^{2} r^{2}}',
        'Radiance leaving a diffuse surfel (Lambert) lit at incidence θ_i.',
        None,
    ),
    'rsm.radiant_exitance': (
        'M = \\frac{\\Phi_{L} c_{\\mathrm{diff}} \\max\\left(0, \\cos{\\left(\\theta_{i} '
        '\\right)}\\right)}{4 \\pi r^{2}}',
        'Radiant exitance: the integral of L_o cos θ_o dω over the hemisphere, π·L_o.',
        None,
    ),
    'rsm.outgoing_flux_area': (
        '\\Phi_{o} = \\frac{A \\Phi_{L} c_{\\mathrm{diff}} \\max\\left(0, '
        '\\cos{\\left(\\theta_{i} \\right)}\\right)}{4 \\pi r^{2}}',
        'Flux reflected by a surfel of area A: Φ_o = A·M.',
        None,
    ),
    'rsm.outgoing_flux': (
        '\\Phi_{o} = \\frac{\\Delta\\omega_{\\mathrm{texel}} \\Phi_{L} c_{\\mathrm{diff}} '
        '\\max\\left(0, \\cos{\\left(\\theta_{i} \\right)}\\right)}{4 \\pi}',
        'Flux reflected by an RSM texel of solid angle Δω_texel = A/r²: '
        'c_diff·Δω_texel/(4π)·Φ_L·max(0, cos θ_i).',
        None,
    ),
    'rsm.texel_flux': (
        '\\Phi_{o} = \\frac{\\Delta\\omega_{\\mathrm{texel}} \\Phi_{L} c_{\\mathrm{diff}}}{4 '
        '\\pi}',
        'Erratum: flux an RSM texel of solid angle Δω_texel reflects, any incidence on the lit '
        'side: c_diff·Δω_texel/(4π)·Φ_L (the surfel area Δω_texel·r²/cos θ_i cancels the cosine).',
        None,
    ),
    'rsm.texel_flux_published_over_correct': (
        '\\Phi_{o}^{\\mathrm{published}} / \\Phi_{o} = \\cos{\\left(\\theta_{i} \\right)}',
        'The published texel flux over the correct one: cos θ_i, counted twice.',
        None,
    ),
    'rsm.pixel_solid_angle_approx': (
        '\\Delta\\omega_{\\mathrm{texel}} = \\frac{2 \\pi}{3 H W}',
        'Per-texel solid angle of a 90° frustum, approximated as (4π/6)/(W·H).',
        None,
    ),
    'rsm.pixel_solid_angle_exact': (
        '\\Delta\\omega_{ij} = \\operatorname{atan}{\\left(\\frac{\\left(-1 + \\frac{2 '
        'j}{H}\\right) \\left(-1 + \\frac{2 i}{W}\\right)}{\\sqrt{\\left(-1 + \\frac{2 '
        'j}{H}\\right)^{2} + \\left(-1 + \\frac{2 i}{W}\\right)^{2} + 1}} \\right)} - '
        '\\operatorname{atan}{\\left(\\frac{\\left(-1 + \\frac{2 j}{H}\\right) \\left(-1 + '
        '\\frac{2 i + 2}{W}\\right)}{\\sqrt{\\left(-1 + \\frac{2 j}{H}\\right)^{2} + \\left(-1 + '
        '\\frac{2 i + 2}{W}\\right)^{2} + 1}} \\right)} - '
        '\\operatorname{atan}{\\left(\\frac{\\left(-1 + \\frac{2 j + 2}{H}\\right) \\left(-1 + '
        '\\frac{2 i}{W}\\right)}{\\sqrt{\\left(-1 + \\frac{2 j + 2}{H}\\right)^{2} + \\left(-1 + '
        '\\frac{2 i}{W}\\right)^{2} + 1}} \\right)} + '
        '\\operatorname{atan}{\\left(\\frac{\\left(-1 + \\frac{2 j + 2}{H}\\right) \\left(-1 + '
        '\\frac{2 i + 2}{W}\\right)}{\\sqrt{\\left(-1 + \\frac{2 j + 2}{H}\\right)^{2} + '
        '\\left(-1 + \\frac{2 i + 2}{W}\\right)^{2} + 1}} \\right)}',
        'Exact solid angle of texel (i, j) of a W×H 90° frustum (rectangle formula).',
        None,
    ),
    'rsm.pixel_solid_angle_corners': (
        '\\Delta\\omega_{ij} = F{\\left(u_{i},v_{j} \\right)} - F{\\left(u_{i},v_{j+1} \\right)} '
        '- F{\\left(u_{i+1},v_{j} \\right)} + F{\\left(u_{i+1},v_{j+1} \\right)}',
        "Exact solid angle of texel (i, j) from the corner function F at the texel's edges u_i = "
        '−1 + 2i/W, v_j = −1 + 2j/H on the image plane z = 1.',
        None,
    ),
    'rsm.corner_function': (
        'F{\\left(u,v \\right)} = \\operatorname{atan}{\\left(\\frac{u v}{\\sqrt{u^{2} + v^{2} + '
        '1}} \\right)}',
        "The rectangle formula's corner function on the image plane z = 1.",
        None,
    ),
    'rsm.pixel_ratio_centre': (
        '\\frac{\\Delta\\omega_{\\mathrm{texel}}}{\\Delta\\omega_{ij}}\\Big|_{\\mathrm{centre}} '
        '= \\frac{\\pi}{6}',
        'Large-map limit of approximate/exact texel solid angle at the centre: π/6.',
        0.5235987755982989,
    ),
    'rsm.pixel_ratio_corner': (
        '\\frac{\\Delta\\omega_{\\mathrm{texel}}}{\\Delta\\omega_{ij}}\\Big|_{\\mathrm{corner}} '
        '= \\frac{\\sqrt{3} \\pi}{2}',
        'Large-map limit of approximate/exact texel solid angle in a corner: √3π/2.',
        2.720699046351327,
    ),
    'rsm.surfel_area': (
        'A_{\\mathrm{texel}} = \\frac{4 w^{2}}{H W}',
        'World area of an RSM texel at view depth w (90° frustum): 4w²/(W·H).',
        None,
    ),
    'rsm.spot_falloff': (
        'f = - \\frac{2 \\left(\\cos\\theta - '
        '\\cos\\theta_{o}\\right)^{3}}{\\left(\\cos\\theta_{i} - \\cos\\theta_{o}\\right)^{3}} + '
        '\\frac{3 \\left(\\cos\\theta - \\cos\\theta_{o}\\right)^{2}}{\\left(\\cos\\theta_{i} - '
        '\\cos\\theta_{o}\\right)^{2}}',
        'Spot cone falloff between the inner and outer angles: smoothstep of cos θ, 3t² − 2t³ '
        'with t = (cos θ − cos θ_o)/(cos θ_i − cos θ_o).',
        None,
    ),
    'rsm.cone_solid_angle': (
        '\\int_{S^2} f \\, d\\omega = - \\pi \\left(\\cos\\theta_{i} + \\cos\\theta_{o} - '
        '2\\right)',
        "Solid angle the spot cone's falloff weights, ∫f dω = 2π(1 − (cos θ_i + cos θ_o)/2): "
        'exact, f being a polynomial in cos θ.',
        None,
    ),
    'rsm.cone_total_flux': (
        '\\Phi_{\\mathrm{cone}} = \\frac{\\Phi_{L} c_{\\mathrm{diff}} \\left(- \\cos\\theta_{i} '
        '- \\cos\\theta_{o} + 2\\right)}{4}',
        'Flux reflected by a surface that catches the whole cone: c_diff·Φ_L·(1 − (cos θ_i + cos '
        'θ_o)/2)/2.',
        None,
    ),
    'rsm.point_light_room_flux': (
        '\\Phi_{\\mathrm{room}} = \\Phi_{L} c_{\\mathrm{diff}}',
        "Flux a point light's six RSM faces (90° frusta along ±x, ±y, ±z, one cube face each) "
        'reflect in a closed room of reflectance c_diff: c_diff·Φ_L.',
        None,
    ),
    'rsm.cone_surfel_area': (
        'A_{\\mathrm{texel}}^{\\mathrm{cone}} = \\frac{4 w^{2} \\tan^{2}{\\left(\\theta_{o} '
        '\\right)}}{H W}',
        'World area of an RSM texel at view depth w when the square frustum holds the outer cone '
        'θ_o: 4w²tan²θ_o/(W·H).',
        None,
    ),
    'corrections.injection_pi.original': (
        'I_{p} = \\Phi_{p} \\max\\left(0, \\cos{\\left(\\theta \\right)}\\right)',
        'VPL intensity as published (Crytek): emits π·Φ_p.',
        None,
    ),
    'corrections.injection_pi.corrected': (
        'I_{p} = \\frac{\\Phi_{p} \\max\\left(0, \\cos{\\left(\\theta \\right)}\\right)}{\\pi}',
        'VPL intensity normalised by 1/π: emits exactly Φ_p.',
        None,
    ),
    'corrections.injection_pi.flux_factor': (
        '\\frac{\\Phi_{\\mathrm{corrected}}}{\\Phi_{\\mathrm{published}}} = \\frac{1}{\\pi}',
        'Corrected ÷ published VPL intensity: 1/π.',
        0.3183098861837907,
    ),
    'corrections.propagation_4pi.original': (
        '\\Phi_{f} = \\frac{\\Delta\\omega_{f} I_{c}}{4 \\pi}',
        'Flux onto a face as published: Δω_f/(4π)·I(ω_c).',
        None,
    ),
    'corrections.propagation_4pi.corrected': (
        '\\Phi_{f} = \\Delta\\omega_{f} I_{c}',
        'Flux onto a face: Δω_f·I(ω_c) = ∫_face I dω for constant I.',
        None,
    ),
    'corrections.propagation_4pi.flux_factor': (
        '\\frac{\\Phi_{\\mathrm{corrected}}}{\\Phi_{\\mathrm{published}}} = 4 \\pi',
        'Corrected ÷ published face flux: 4π.',
        12.566370614359172,
    ),
    'corrections.reprojection_pi.original': (
        '\\Phi_{\\mathrm{lobe}} = \\frac{\\Phi_{f}}{\\pi}',
        'Reprojected flux as published: Φ_lobe = Φ_f/π (loses 1 − 1/π).',
        None,
    ),
    'corrections.reprojection_pi.corrected': (
        '\\Phi_{\\mathrm{lobe}} = \\Phi_{f}',
        'Reprojected flux: Φ_lobe = Φ_f (the lobe re-emits all of it).',
        None,
    ),
    'corrections.reprojection_pi.flux_factor': (
        '\\frac{\\Phi_{\\mathrm{corrected}}}{\\Phi_{\\mathrm{published}}} = \\pi',
        'Corrected ÷ published reprojected flux: π.',
        3.141592653589793,
    ),
    'corrections.injection_pi.emitted_original': (
        '\\Phi_{emitted} = \\pi \\Phi_{p}',
        '∫ Φ_p·max(0, ⟨n_p, ω⟩) dω = π·Φ_p: the published VPL emits π times its flux.',
        None,
    ),
    'corrections.injection_pi.emitted_corrected': (
        '\\Phi_{emitted} = \\Phi_{p}',
        '∫ Φ_p/π·max(0, ⟨n_p, ω⟩) dω = Φ_p: the corrected VPL emits its flux.',
        None,
    ),
    'corrections.propagation_4pi.exact_face_flux': (
        '\\Phi_{f} = \\Delta\\omega_{f} I_{c}',
        'Flux of a constant intensity through a face: ∫_face I dω = Δω_f·I.',
        None,
    ),
    'corrections.reprojection_pi.reprojected_original': (
        '\\Phi_{reprojected} = \\frac{\\Phi_{f}}{\\pi}',
        "The published reprojection re-emits Φ_f/π of the face's flux Φ_f.",
        None,
    ),
    'corrections.reprojection_pi.reprojected_corrected': (
        '\\Phi_{reprojected} = \\Phi_{f}',
        "The corrected reprojection re-emits all of the face's flux Φ_f.",
        None,
    ),
    'corrections.exact_constants.original': (
        '\\left[\\begin{matrix}\\Delta\\omega_{\\mathrm{front}}\\\\\\Delta\\omega_{\\mathrm{side}'
        '}\\\\\\pi_{\\mathrm{formula}}\\end{matrix}\\right] = '
        '\\left[\\begin{matrix}0.4006696846\\\\0.4234413544\\\\3.1415926\\end{matrix}\\right]',
        'Front and side solid angles and π as the DX11 article prints them.',
        None,
    ),
    'corrections.exact_constants.corrected': (
        '\\left[\\begin{matrix}\\Delta\\omega_{\\mathrm{front}}\\\\\\Delta\\omega_{\\mathrm{side}'
        '}\\\\\\pi_{\\mathrm{formula}}\\end{matrix}\\right] = \\left[\\begin{matrix}4 '
        '\\operatorname{atan}{\\left(\\frac{\\sqrt{11}}{33} \\right)}\\\\- \\frac{\\pi}{3} + 2 '
        '\\operatorname{atan}{\\left(\\frac{3 \\sqrt{11}}{11} '
        '\\right)}\\\\\\pi\\end{matrix}\\right]',
        'The exact solid angles of the front and side faces and π.',
        None,
    ),
    'corrections.exact_constants.step_flux_original': (
        '\\frac{\\Phi_{t+1}}{\\Phi_{t}} = \\frac{31416526533}{31415926000}',
        'One step with the printed constants (other corrections on): 6(Δω_front + '
        '4Δω_side)/(4π_f) of the flux, not 1.',
        1.000019115559414,
    ),
    'corrections.exact_constants.step_flux_corrected': (
        '\\frac{\\Phi_{t+1}}{\\Phi_{t}} = 1',
        'One step with the exact constants keeps the flux: 6(Δω_front + 4Δω_side) = 4π.',
        1.0,
    ),
    'corrections.exact_constants.injected_flux_original': (
        '\\frac{\\Phi_{injected}}{\\Phi_{p}} = \\frac{5000000 \\pi}{15707963}',
        'A VPL injected with k_I = 1/3.1415926 emits π/3.1415926 of its flux.',
        1.0000000170581613,
    ),
    'corrections.exact_constants.flux_factor': (
        '\\frac{\\Phi_{\\mathrm{corrected}}}{\\Phi_{\\mathrm{published}}} = '
        '\\frac{31415926000}{31416526533}',
        'Corrected ÷ published flux after one step: 31415926000/31416526533.',
        0.9999808848059836,
    ),
    'corrections.side_faces.original': (
        '\\Phi_{t+1} = \\frac{3 \\Delta\\omega_{\\mathrm{front}} \\Phi_{t}}{2 \\pi}',
        'Front faces only: one step sends 6Δω_front/(4π) of the flux on.',
        None,
    ),
    'corrections.side_faces.corrected': (
        '\\Phi_{t+1} = \\frac{3 \\Phi_{t} \\left(\\Delta\\omega_{\\mathrm{front}} + 4 '
        '\\Delta\\omega_{\\mathrm{side}}\\right)}{2 \\pi}',
        'Front + 4 side faces per neighbour: 6(Δω_front + 4Δω_side)/(4π) of the flux.',
        None,
    ),
    'corrections.side_faces.step_flux_original': (
        '\\frac{\\Phi_{t+1}}{\\Phi_{t}} = \\frac{6 '
        '\\operatorname{atan}{\\left(\\frac{\\sqrt{11}}{33} \\right)}}{\\pi}',
        'Front faces only, one step keeps 6·atan(√11/33)/π ≈ 0.19 of the flux.',
        0.19130568257555955,
    ),
    'corrections.side_faces.step_flux_corrected': (
        '\\frac{\\Phi_{t+1}}{\\Phi_{t}} = 1',
        'All five faces: one step keeps all the flux.',
        1.0,
    ),
    'corrections.side_faces.flux_factor': (
        '\\frac{\\Phi_{\\mathrm{5\\ faces}}}{\\Phi_{\\mathrm{front\\ only}}} = \\frac{\\pi}{6 '
        '\\operatorname{atan}{\\left(\\frac{\\sqrt{11}}{33} \\right)}}',
        'Corrected ÷ front-only flux after one step: π/(6·atan(√11/33)).',
        5.227236256325174,
    ),
    'corrections.surfel_area_squared.original': (
        'A_{s} = \\frac{4 w}{H W}',
        'Surfel area growing linearly with view depth w (the bug of annotations §5).',
        None,
    ),
    'corrections.surfel_area_squared.corrected': (
        'A_{s} = \\frac{4 w^{2}}{H W}',
        'Surfel area of a 90° W×H texel at view depth w: 4w²/(W·H).',
        None,
    ),
    'corrections.surfel_area_squared.flux_factor': (
        'A_{w^{2}} / A_{w} = w',
        'Squared ÷ linear surfel area (and occluder weight): w, so the linear area is too small '
        'beyond w = 1 and too large nearer.',
        None,
    ),
    'corrections.ping_pong.original': (
        'acc_{t} = acc_{t-1} + P{\\left(acc_{t-1} \\right)}',
        'DX11 in-place update, read race-free: light already propagated is propagated again (the '
        'GPU version also races).',
        None,
    ),
    'corrections.ping_pong.corrected': (
        'acc_{t} = acc_{t-1} + P{\\left(grid_{t-1} \\right)}',
        "Ping-pong: only the light in flight moves on, the last step's light propagated once.",
        None,
    ),
    'corrections.ping_pong.accumulated_original': (
        'acc_{N} = grid_{0} \\left(P + 1\\right)^{N}',
        'In place after N steps: the injected light propagated k times is counted C(N, k) times.',
        None,
    ),
    'corrections.ping_pong.accumulated_corrected': (
        'acc_{N} = grid_{0} \\sum_{t=0}^{N} P^{t}',
        'Ping-pong after N steps: each power of P once.',
        None,
    ),
    'corrections.ping_pong.flux_original': (
        '\\frac{\\Phi_{N}}{\\Phi_{0}} = \\left(p + 1\\right)^{N}',
        'In place, a step scaling flux by p accumulates (1 + p)^N: unbounded for any p > 0.',
        None,
    ),
    'corrections.ping_pong.flux_corrected': (
        '\\frac{\\Phi_{N}}{\\Phi_{0}} = \\sum_{t=0}^{N} p^{t}',
        'Ping-pong accumulates the geometric series Σ p^t (→ 1/(1 − p) for p < 1).',
        None,
    ),
    'corrections.ping_pong.flux_factor': (
        '\\frac{\\Phi_{\\mathrm{ping\\ pong}}}{\\Phi_{\\mathrm{in\\ place}}} = 2^{- N} \\left(N '
        '+ 1\\right)',
        'Ping-pong ÷ in place accumulated flux for a flux-conserving step (p = 1): (N + 1)/2^N.',
        None,
    ),
    'corrections.clamp_front_face.original': (
        'I_{f} = I{\\left(\\omega_{c} \\right)}',
        'Front-face intensity unclamped: negative SH lobes send negative light.',
        None,
    ),
    'corrections.clamp_front_face.corrected': (
        'I_{f} = \\max\\left(0, I{\\left(\\omega_{c} \\right)}\\right)',
        'Front-face intensity clamped at zero, as the DX11 propagation shader does.',
        None,
    ),
    'corrections.clamp_front_face.clamp_gain': (
        '\\Delta I_{f} = \\max\\left(0, - I{\\left(\\omega_{c} \\right)}\\right)',
        "Clamped − unclamped front-face intensity: max(0, −I) ≥ 0, the audit's clamp gain.",
        None,
    ),
    'corrections.clamp_front_face.lobe_behind': (
        'I_{L1}{\\left(- n \\right)} = - \\frac{1}{4}',
        'The L1 lobe of max(0, ⟨n, ω⟩) (1/4 + ⟨n, ω⟩/2) behind itself, ω = −n: −1/4 where the '
        'lobe it approximates is 0.',
        -0.25,
    ),
    'corrections.irradiance_gather.original': (
        'E = \\max\\left(0, \\frac{\\sqrt{3} n_{x} s_{3}}{2 \\sqrt{\\pi}} + \\frac{\\sqrt{3} '
        'n_{y} s_{1}}{2 \\sqrt{\\pi}} - \\frac{\\sqrt{3} n_{z} s_{2}}{2 \\sqrt{\\pi}} + '
        '\\frac{s_{0}}{2 \\sqrt{\\pi}}\\right)',
        'The DX11 gather: ⟨s, Y(−n)⟩, the intensity toward −n (W/sr), clamped, read as the '
        'irradiance: no cosine lobe and no 1/h².',
        None,
    ),
    'corrections.irradiance_gather.corrected': (
        'E = \\frac{\\max\\left(0, \\frac{\\sqrt{3} \\sqrt{\\pi} n_{x} s_{3}}{3} + '
        '\\frac{\\sqrt{3} \\sqrt{\\pi} n_{y} s_{1}}{3} - \\frac{\\sqrt{3} \\sqrt{\\pi} n_{z} '
        's_{2}}{3} + \\frac{\\sqrt{\\pi} s_{0}}{2}\\right)}{h^{2}}',
        'The irradiance of the light the cell holds: ⟨s, lobe(−n)⟩/h², clamped.',
        None,
    ),
    'corrections.irradiance_gather.band0_factor': (
        '\\mathrm{lobe}_0 / Y_0 = \\pi',
        'Band 0 of lobe(−n) ÷ band 0 of Y(−n): π (√π/2 against 1/(2√π)).',
        3.141592653589793,
    ),
    'corrections.irradiance_gather.band1_factor': (
        '\\mathrm{lobe}_2 / Y_2 = \\frac{2 \\pi}{3}',
        'Band 1 of lobe(−n) ÷ band 1 of Y(−n): 2π/3 (√(π/3) against √3/(2√π)).',
        2.0943951023931957,
    ),
    'corrections.irradiance_gather.flux_factor': (
        'E_{\\mathrm{corrected}} / E_{\\mathrm{DX11}} = \\frac{\\pi}{h^{2}}',
        'Corrected ÷ DX11 for light of the same intensity in every direction (band 0 only): '
        'π/h², so the DX11 gather is too bright in cells smaller than √π.',
        None,
    ),
    'corrections.model_face_weights.original': (
        '\\left[\\begin{matrix}w_{front}\\\\w_{side}\\end{matrix}\\right] = '
        '\\left[\\begin{matrix}\\frac{\\Delta\\omega_{\\mathrm{front}}}{2 '
        '\\pi}\\\\\\frac{\\Delta\\omega_{\\mathrm{side}}}{3 \\pi}\\end{matrix}\\right]',
        "The DX11 shader's whole factor of a face, in place of k_R·k_I·k_P·Δω_f: Δω_front/(2π) "
        'for a front face, Δω_side/(3π) for a side face.',
        None,
    ),
    'corrections.model_face_weights.corrected': (
        '\\left[\\begin{matrix}w_{front}\\\\w_{side}\\end{matrix}\\right] = '
        '\\left[\\begin{matrix}\\frac{\\Delta\\omega_{\\mathrm{front}}}{\\pi}\\\\\\frac{\\Delta\\'
        'omega_{\\mathrm{side}}}{\\pi}\\end{matrix}\\right]',
        "The model's k_R·k_I·k_P·Δω_f with the corrected factors (k_R·k_I·k_P = 1/π) for every "
        'face.',
        None,
    ),
    'corrections.model_face_weights.step_flux_original': (
        '\\frac{\\Phi_{t+1}}{\\Phi_{t}} = - \\frac{2 \\operatorname{atan}{\\left(\\frac{3 '
        '\\sqrt{11}}{11} \\right)}}{\\pi} + \\frac{5}{6}',
        'One step with the DX11 face weights keeps (3Δω_front + 8Δω_side)/(4π) = 5/6 − '
        '2·atan(3√11/11)/π ≈ 0.365 of the flux.',
        0.36521761376259326,
    ),
    'corrections.model_face_weights.flux_factor': (
        '\\frac{\\Phi_{\\mathrm{corrected}}}{\\Phi_{\\mathrm{published}}} = \\frac{6 \\pi}{- 12 '
        '\\operatorname{atan}{\\left(\\frac{3 \\sqrt{11}}{11} \\right)} + 5 \\pi}',
        'Corrected ÷ DX11 flux after one step: 1/(5/6 − 2·atan(3√11/11)/π) ≈ 2.74.',
        2.738093570289964,
    ),
    'propagation.side_eval_direction': (
        'e_{\\mathrm{side}} = \\left[\\begin{matrix}\\frac{\\sqrt{5}}{5}\\\\\\frac{2 '
        '\\sqrt{5}}{5}\\\\0\\end{matrix}\\right]',
        'Evaluation direction of the side face x = 1/2 of the neighbour along +y: towards the '
        'face centre (1/2, 1, 0).',
        None,
    ),
    'propagation.side_eval_small': (
        'e_{\\mathrm{side},x} = \\frac{\\sqrt{5}}{5}',
        'Side-face evaluation direction: component along the side normal, 1/√5.',
        0.4472135954999579,
    ),
    'propagation.side_eval_big': (
        'e_{\\mathrm{side},y} = \\frac{2 \\sqrt{5}}{5}',
        'Side-face evaluation direction: component along the propagation axis, 2/√5.',
        0.8944271909999159,
    ),
    'propagation.side_reprojection_direction': (
        'r_{\\mathrm{side}} = \\left[\\begin{matrix}1\\\\0\\\\0\\end{matrix}\\right]',
        'Side-face reprojection direction: the face normal (here +x).',
        None,
    ),
    'propagation.front_reprojection_direction': (
        'e_{\\mathrm{front}} = r_{\\mathrm{front}} = '
        '\\left[\\begin{matrix}0\\\\1\\\\0\\end{matrix}\\right]',
        'Front-face evaluation and reprojection direction: the propagation axis (here +y).',
        None,
    ),
    'propagation.l2_face_basis_sums': (
        '\\Big(\\sum_{f} Y_{k}(e_{f})\\Big) = \\left[\\begin{matrix}\\frac{3}{\\sqrt{\\pi}} & '
        '\\frac{12}{\\sqrt{\\pi}}\\\\0 & 0\\\\0 & 0\\\\0 & 0\\\\0 & 0\\\\0 & 0\\\\0 & 0\\\\0 & '
        '0\\\\0 & 0\\end{matrix}\\right]',
        'Σ Y_k(e_f) of the L2 basis over the 6 front faces (column 0) and the 24 side faces '
        '(column 1): only band 0 survives, so a corrected L2 step conserves flux like an L1 step.',
        None,
    ),
    'propagation.step_flux_factor': (
        '\\frac{\\Phi_{t+1}}{\\Phi_{t}} = \\pi k_{I} k_{P} k_{R}',
        'Flux after ÷ before one propagation step, without clamping, occlusion or border: '
        'π·k_R·k_I·k_P.',
        None,
    ),
    'propagation.step_flux_factor_original': (
        '\\frac{\\Phi_{t+1}}{\\Phi_{t}}\\Big|_{\\mathrm{published}} = \\frac{1}{4 \\pi}',
        'One propagation step with the published formulas keeps 1/(4π) of the flux.',
        0.07957747154594767,
    ),
    'propagation.step_flux_factor_corrected': (
        '\\frac{\\Phi_{t+1}}{\\Phi_{t}}\\Big|_{\\mathrm{corrected}} = 1',
        'One propagation step with the corrected formulas keeps all the flux.',
        1.0,
    ),
    'propagation.step_flux_factor_dx11': (
        '\\frac{\\Phi_{t+1}}{\\Phi_{t}}\\Big|_{\\mathrm{DX11}} = - \\frac{2 '
        '\\operatorname{atan}{\\left(\\frac{3 \\sqrt{11}}{11} \\right)}}{\\pi} + \\frac{5}{6}',
        'One step of the DX11 shader (weights Δω/(2π) front, Δω/(3π) side): (3Δω_front + '
        '8Δω_side)/(4π).',
        0.36521761376259326,
    ),
    'propagation.front_weight_dx11': (
        'w_{\\mathrm{front}}^{\\mathrm{DX11}} / \\Delta\\omega_{\\mathrm{front}} = \\frac{1}{2 '
        '\\pi}',
        'DX11 front-face factor ÷ Δω_front, the whole factor of the face: 1/(2π) (corrected '
        'model: k_P·k_R·k_I = 1/π; published: 1/(4π²)).',
        0.15915494309189535,
    ),
    'propagation.side_weight_dx11': (
        'w_{\\mathrm{side}}^{\\mathrm{DX11}} / \\Delta\\omega_{\\mathrm{side}} = \\frac{1}{3 '
        '\\pi}',
        'DX11 side-face factor ÷ Δω_side, the whole factor of the face: 1/(3π) (corrected model: '
        'k_P·k_R·k_I = 1/π; published: 1/(4π²)).',
        0.1061032953945969,
    ),
    'propagation.front_share_dx11': (
        '\\pi\\, w_{\\mathrm{front}}^{\\mathrm{DX11}} / \\Delta\\omega_{\\mathrm{front}} = '
        '\\frac{1}{2}',
        "DX11 front-face factor ÷ the corrected model's 1/π: 1/2 (the shader's Δω_front/PI/2).",
        0.5,
    ),
    'propagation.side_share_dx11': (
        '\\pi\\, w_{\\mathrm{side}}^{\\mathrm{DX11}} / \\Delta\\omega_{\\mathrm{side}} = '
        '\\frac{1}{3}',
        "DX11 side-face factor ÷ the corrected model's 1/π: 1/3 (the shader's Δω_side/PI/3).",
        0.3333333333333333,
    ),
    'neighbours26.edge_face': (
        '\\Delta\\omega_{\\mathrm{edge}} = - 2 '
        '\\operatorname{atan}{\\left(\\frac{\\sqrt{11}}{33} \\right)} + 2 '
        '\\operatorname{atan}{\\left(\\frac{\\sqrt{19}}{19} \\right)}',
        "Solid angle of one of an edge neighbour's two outer faces (on the surface of the 3×3×3 "
        'block) seen from the source cell centre.',
        0.2506919694731428,
    ),
    'neighbours26.corner_face': (
        '\\Delta\\omega_{\\mathrm{corner}} = - 2 '
        '\\operatorname{atan}{\\left(\\frac{\\sqrt{19}}{19} \\right)} + '
        '\\operatorname{atan}{\\left(\\frac{\\sqrt{11}}{33} \\right)} + \\frac{\\pi}{6}',
        "Solid angle of one of a corner neighbour's three outer faces seen from the source cell "
        'centre.',
        0.17273938496359623,
    ),
    'neighbours26.edge_eval_big': (
        'e_{\\mathrm{edge},x} = \\frac{3 \\sqrt{13}}{13}',
        'Edge-face evaluation direction: component along the face normal, 3/√13.',
        0.8320502943378437,
    ),
    'neighbours26.edge_eval_small': (
        'e_{\\mathrm{edge},z} = \\frac{2 \\sqrt{13}}{13}',
        'Edge-face evaluation direction: component along the other offset axis, 2/√13.',
        0.5547001962252291,
    ),
    'neighbours26.corner_eval_big': (
        'e_{\\mathrm{corner},x} = \\frac{3 \\sqrt{17}}{17}',
        'Corner-face evaluation direction: component along the face normal, 3/√17.',
        0.7276068751089989,
    ),
    'neighbours26.corner_eval_small': (
        'e_{\\mathrm{corner},y} = \\frac{2 \\sqrt{17}}{17}',
        'Corner-face evaluation direction: component along each other axis, 2/√17.',
        0.48507125007266594,
    ),
    'neighbours26.tiling': (
        '4 \\pi = 4 \\pi',
        'The 54 outer faces of the 26 neighbours cover the sphere exactly once.',
        12.566370614359172,
    ),
    'neighbours26.block_face_tiling': (
        '\\frac{2 \\pi}{3} = \\frac{2 \\pi}{3}',
        'One face of the 3×3×3 block: a front, four edge and four corner faces, 2π/3.',
        2.0943951023931957,
    ),
    'neighbours26.step_flux_factor': (
        '\\Phi_{t}/\\Phi_{t-1}\\big|_{26} = 1',
        'Flux after ÷ before one corrected 26-neighbour step (L1 or L2), without clamping, '
        'occlusion or border.',
        1.0,
    ),
    'occlusion.one_sided': (
        'B(n) = \\left[\\begin{matrix}\\frac{\\sqrt{\\pi} A}{2 s^{2}}\\\\- \\frac{\\sqrt{3} '
        '\\sqrt{\\pi} A n_{y}}{3 s^{2}}\\\\\\frac{\\sqrt{3} \\sqrt{\\pi} A n_{z}}{3 s^{2}}\\\\- '
        '\\frac{\\sqrt{3} \\sqrt{\\pi} A n_{x}}{3 s^{2}}\\end{matrix}\\right]',
        'Geometry-volume SH added by a one-sided occluder surfel of area A (cell size s).',
        None,
    ),
    'occlusion.double_sided_lobe': (
        '\\mathrm{lobe}(n) + \\mathrm{lobe}(-n) = '
        '\\left[\\begin{matrix}\\sqrt{\\pi}\\\\0\\\\0\\\\0\\end{matrix}\\right]',
        'lobe(n) + lobe(−n): band 1 cancels for every normal n, leaving (√π, 0, 0, 0).',
        None,
    ),
    'occlusion.double_sided_blocking': (
        'B_{\\mathrm{double}} \\, s^{2} / A = \\frac{1}{2}',
        'A double-sided surfel blocks the same amount, 1/2 per unit A/s², in every direction.',
        0.5,
    ),
    'occlusion.camera_surfel_area': (
        'A_{\\mathrm{pixel}} = \\frac{4 w^{2} \\tan^{2}{\\left(\\frac{\\theta_{y}}{2} '
        '\\right)}}{H^{2}}',
        'World area of a camera pixel at view depth w on a plane facing the camera (vertical '
        "field of view θ_y, H pixels high): the RSM texel's rule.",
        None,
    ),
    'occlusion.statistical_visibility': (
        'V_{\\mathrm{stat}}(\\tau) = e^{- \\tau}',
        'Visibility of a face of blocking τ shared by many small surfels placed independently at '
        'random: lim (1 − τ/m)^m = exp(−τ).',
        None,
    ),
    'occlusion.statistical_first_order': (
        'V_{\\mathrm{stat}}(\\tau) + O(\\tau^{2}) = 1 - \\tau',
        "exp(−τ) to first order in τ: the LPV paper's linear blocker 1 − τ.",
        None,
    ),
    'occlusion.reprojection_depth_bound': (
        '\\max |\\Delta d| = \\frac{\\sqrt{2} \\delta \\tan{\\left(\\theta \\right)}}{2}',
        "How far the shadow map's stored depth can differ from a point's own depth on the same "
        'plane: half a texel diagonal times tan θ.',
        None,
    ),
    'media.isotropic_phase': (
        'p_{\\mathrm{iso}} = \\frac{1}{4 \\pi}',
        'The isotropic phase function, 1/(4π) per steradian.',
        0.07957747154594767,
    ),
    'media.isotropic_normalisation': (
        '\\int_{S^2} p_{\\mathrm{iso}} \\, d\\omega = 1',
        'The isotropic phase function integrates to 1 over the sphere.',
        1.0,
    ),
    'media.hg_phase': (
        'p_{\\mathrm{HG}} = \\frac{1 - g^{2}}{4 \\pi \\left(g^{2} - 2 g t + '
        '1\\right)^{\\frac{3}{2}}}',
        'Henyey–Greenstein phase function at the scattering cosine t, asymmetry g.',
        None,
    ),
    'media.hg_normalisation': (
        '\\int_{S^2} p_{\\mathrm{HG}} \\, d\\omega = 1',
        'The HG phase function integrates to 1 over the sphere for every g.',
        1.0,
    ),
    'media.hg_band_factors': (
        '(a_{0}, a_{1}, a_{2}, a_{3})_{\\mathrm{HG}} = '
        '\\left[\\begin{matrix}1\\\\g\\\\g^{2}\\\\g^{3}\\end{matrix}\\right]',
        'SH convolution factors a_l = 2π∫p_HG P_l dt of the HG lobe, bands 0..3: g^l exactly '
        '(Funk–Hecke).',
        None,
    ),
    'media.hg_zonal_coefficients': (
        '\\Big(\\int_{S^2} p_{\\mathrm{HG}} Y_{l0} \\, d\\omega\\Big) = '
        '\\left[\\begin{matrix}\\frac{1}{2 \\sqrt{\\pi}}\\\\\\frac{\\sqrt{3} g}{2 '
        '\\sqrt{\\pi}}\\\\\\frac{\\sqrt{5} g^{2}}{2 \\sqrt{\\pi}}\\\\\\frac{\\sqrt{7} g^{3}}{2 '
        '\\sqrt{\\pi}}\\end{matrix}\\right]',
        'Zonal SH coefficients of the HG lobe around +z: g^l·√((2l+1)/(4π)).',
        None,
    ),
    'media.isotropic_band_factors': (
        '(a_{0}, a_{1}, a_{2}, a_{3})_{\\mathrm{iso}} = '
        '\\left[\\begin{matrix}1\\\\0\\\\0\\\\0\\end{matrix}\\right]',
        'SH convolution factors of the isotropic phase function: band 0 only.',
        None,
    ),
    'media.transmittance': (
        'T = e^{- \\ell \\sigma_{t}}',
        'Transmittance of a homogeneous medium over a length ℓ (Beer–Lambert).',
        None,
    ),
    'media.segment_inscatter': (
        'L_{s} = L_{p} \\alpha \\left(1 - e^{- \\ell \\sigma_{t}}\\right)',
        'Single scattering of a constant in-scattered radiance L_p over a ray of length ℓ: '
        'α·L_p·(1 − exp(−σ_t·ℓ)).',
        None,
    ),
    'errata.annotations.front_corner_dot_adjacent': (
        '\\left(c_{1} \\cdot c_{2}\\right)^{\\mathrm{printed}} = \\frac{9}{11}',
        'front face: c1·c2 (adjacent corners) as printed in Kirsch, "Light Propagation Volumes — '
        'Annotations" (2010) (§2.1 front-face worksheet, eq. (5)): 9/11.',
        0.8181818181818182,
    ),
    'errata.annotations.front_corner_dot_diagonal': (
        '\\left(c_{3} \\cdot c_{2}\\right)^{\\mathrm{printed}} = \\frac{7}{11}',
        'front face: c3·c2 (diagonal corners) as printed in Kirsch, "Light Propagation Volumes — '
        'Annotations" (2010) (§2.1 front-face worksheet, eq. (7)): 7/11.',
        0.6363636363636364,
    ),
    'errata.annotations.front_maple_delta': (
        '\\delta^{\\mathrm{printed}} = \\pi - \\operatorname{acos}{\\left(0.1 \\right)}',
        'front face: angle δ at a corner as printed in Kirsch, "Light Propagation Volumes — '
        'Annotations" (2010) (§2.1 front-face worksheet, eq. (10)): π − arccos(1/10).',
        1.6709637479564565,
    ),
    'errata.annotations.front_maple_alpha': (
        '\\alpha^{\\mathrm{printed}} = \\operatorname{acos}{\\left(\\frac{3 \\sqrt{5}}{10} '
        '\\right)}',
        'front face: angle α at a corner as printed in Kirsch, "Light Propagation Volumes — '
        'Annotations" (2010) (§2.1 front-face worksheet, eq. (12)): arccos(3/20·√2·√10).',
        0.8354818739782283,
    ),
    'errata.annotations.front_maple_closed_form': (
        '\\Delta\\omega_{\\mathrm{front}}^{\\mathrm{printed}} = - 2 '
        '\\operatorname{acos}{\\left(0.1 \\right)} + 4 \\operatorname{acos}{\\left(\\frac{3 '
        '\\sqrt{5}}{10} \\right)}',
        'front-face solid angle (closed form) as printed in Kirsch, "Light Propagation Volumes — '
        'Annotations" (2010) (§2.1 front-face worksheet, eq. (13)): 4 arccos(3/20·√2·√10) − 2 '
        'arccos(1/10).',
        0.4006696846462392,
    ),
    'errata.annotations.front_maple_decimal': (
        '\\Delta\\omega_{\\mathrm{front}}^{\\mathrm{printed}} = 0.400669685',
        'front-face solid angle as printed in Kirsch, "Light Propagation Volumes — Annotations" '
        "(2010) (§2.1 front-face worksheet, eq. (14) 'at 10 digits'): 0.400669685.",
        0.400669685,
    ),
    'errata.annotations.side_corner_dot': (
        '\\left(c_{2} \\cdot c_{4}\\right)^{\\mathrm{printed}} = \\frac{5 \\sqrt{33}}{33}',
        'side face: c2·c4 as printed in Kirsch, "Light Propagation Volumes — Annotations" (2010) '
        '(§2.1 side-face worksheet, eq. (6)): 5/33·√11·√3.',
        0.8703882797784892,
    ),
    'errata.annotations.side_maple_closed_form': (
        '\\Delta\\omega_{\\mathrm{side}}^{\\mathrm{printed}} = - '
        '\\operatorname{acos}{\\left(\\frac{\\sqrt{3}}{6} \\right)} - '
        '\\operatorname{acos}{\\left(\\frac{3 \\sqrt{5}}{10} \\right)} + '
        '\\operatorname{acos}{\\left(\\frac{7 \\sqrt{15}}{30} \\right)} + \\frac{2 \\pi}{3}',
        'side-face solid angle (closed form) as printed in Kirsch, "Light Propagation Volumes — '
        'Annotations" (2010) (§2.1 side-face worksheet, eq. (21)): −arccos(√11√3√10√66/220) + '
        'arccos(√66√22/44) + arccos(7√11√3√22√10/660) − arccos(√66√22/132) + '
        'arccos(√11√3√22√2/44) + arccos(√11√3√66√2/132).',
        0.42343135443673907,
    ),
    'errata.annotations.side_maple_20_digits': (
        '\\Delta\\omega_{\\mathrm{side}}^{\\mathrm{printed}} = 0.42343135443673907668',
        'side-face solid angle as printed in Kirsch, "Light Propagation Volumes — Annotations" '
        "(2010) (§2.1 side-face worksheet, eq. (22) 'at 20 digits'): 0.42343135443673907668.",
        0.42343135443673907,
    ),
    'errata.annotations.side_maple_5_digits': (
        '\\Delta\\omega_{\\mathrm{side}}^{\\mathrm{printed}} = 0.42347',
        'side-face solid angle as printed in Kirsch, "Light Propagation Volumes — Annotations" '
        "(2010) (§2.1 side-face worksheet, eq. (23) 'at 5 digits'): 0.42347.",
        0.42347,
    ),
    'errata.annotations.front_integral_closed_form': (
        '\\Delta\\omega_{\\mathrm{front}}^{\\mathrm{printed}} = 4 '
        '\\operatorname{atan}{\\left(\\frac{\\sqrt{11}}{33} \\right)}',
        'front-face solid angle (closed form) as printed in Kirsch, "Light Propagation Volumes — '
        'Annotations" (2010) (§2.2 FrontFacingSolidAngle): 4 arctan(1/33·√11).',
        0.4006696846462392,
    ),
    'errata.annotations.front_integral_decimal': (
        '\\Delta\\omega_{\\mathrm{front}}^{\\mathrm{printed}} = 0.4006696844',
        'front-face solid angle as printed in Kirsch, "Light Propagation Volumes — Annotations" '
        "(2010) (§2.2 FrontFacingSolidAngle '= 0.4006696844…'): 0.4006696844.",
        0.4006696844,
    ),
    'errata.annotations.side_integral_closed_form': (
        '\\Delta\\omega_{\\mathrm{side}}^{\\mathrm{printed}} = - \\frac{\\pi}{3} + 2 '
        '\\operatorname{atan}{\\left(\\frac{3 \\sqrt{11}}{11} \\right)}',
        'side-face solid angle (closed form) as printed in Kirsch, "Light Propagation Volumes — '
        'Annotations" (2010) (§2.2 SideFacingSolidAngle): −1/3 π + 2 arctan(3/11·√11).',
        0.42343135443673907,
    ),
    'errata.annotations.side_integral_decimal': (
        '\\Delta\\omega_{\\mathrm{side}}^{\\mathrm{printed}} = 0.423431354',
        'side-face solid angle as printed in Kirsch, "Light Propagation Volumes — Annotations" '
        "(2010) (§2.2 SideFacingSolidAngle '= 0.423431354…'): 0.423431354.",
        0.423431354,
    ),
    'errata.annotations.coslobe_c0': (
        's_{0}^{\\mathrm{printed}} = \\frac{\\sqrt{\\pi}}{2}',
        'clamped cosine lobe s0 as printed in Kirsch, "Light Propagation Volumes — Annotations" '
        '(2010) (§4.3 eq. (12)): √π/2.',
        0.886226925452758,
    ),
    'errata.annotations.coslobe_c1': (
        's_{2}^{\\mathrm{printed}} = \\frac{\\sqrt{3} \\sqrt{\\pi}}{3}',
        'clamped cosine lobe s2 as printed in Kirsch, "Light Propagation Volumes — Annotations" '
        '(2010) (§4.3 eq. (14)): √(π/3).',
        1.0233267079464885,
    ),
    'errata.annotations.side_direction_small': (
        'e_{\\mathrm{side},x}^{\\mathrm{printed}} = \\frac{\\sqrt{5}}{5}',
        'side-face main direction, 1st component as printed in Kirsch, "Light Propagation '
        'Volumes — Annotations" (2010) (§6.1): 1/√5.',
        0.4472135954999579,
    ),
    'errata.annotations.side_direction_big': (
        'e_{\\mathrm{side},y}^{\\mathrm{printed}} = \\frac{2 \\sqrt{5}}{5}',
        'side-face main direction, 2nd component as printed in Kirsch, "Light Propagation '
        'Volumes — Annotations" (2010) (§6.1): 2/√5.',
        0.8944271909999159,
    ),
    'errata.dx11.rsm_vpls': (
        'N_{\\mathrm{VPL}}^{\\mathrm{printed}} = 4194304',
        'VPLs in a 2048×2048 RSM as printed in the DirectX 11 LPV implementation article '
        "(Injection, '2048×2048=4194304'): 4194304.",
        4194304.0,
    ),
    'errata.dx11.sh_c0': (
        '\\mathrm{SH\\_C0}^{\\mathrm{printed}} = 0.282094792',
        'SH_C0 = 1/(2√π) as printed in the DirectX 11 LPV implementation article (#define SH_C0 '
        '(injection, propagation and rendering shaders)): 0.282094792.',
        0.282094792,
    ),
    'errata.dx11.sh_c1': (
        '\\mathrm{SH\\_C1}^{\\mathrm{printed}} = 0.488602512',
        'SH_C1 = √3/(2√π) as printed in the DirectX 11 LPV implementation article (#define '
        'SH_C1): 0.488602512.',
        0.488602512,
    ),
    'errata.dx11.coslobe_c0': (
        '\\mathrm{SH\\_cosLobe\\_C0}^{\\mathrm{printed}} = 0.886226925',
        'SH_cosLobe_C0 = √π/2 as printed in the DirectX 11 LPV implementation article (#define '
        'SH_cosLobe_C0): 0.886226925.',
        0.886226925,
    ),
    'errata.dx11.coslobe_c1': (
        '\\mathrm{SH\\_cosLobe\\_C1}^{\\mathrm{printed}} = 1.02332671',
        'SH_cosLobe_C1 = √(π/3) as printed in the DirectX 11 LPV implementation article (#define '
        'SH_cosLobe_C1): 1.02332671.',
        1.02332671,
    ),
    'errata.dx11.pi': (
        '\\pi^{\\mathrm{printed}} = 3.1415926',
        'PI as printed in the DirectX 11 LPV implementation article (#define PI 3.1415926f (and '
        'Pi in the propagation shader)): 3.1415926.',
        3.1415926,
    ),
    'errata.dx11.front_solid_angle': (
        '\\Delta\\omega_{\\mathrm{front}}^{\\mathrm{printed}} = 0.4006696846',
        'front-face solid angle as printed in the DirectX 11 LPV implementation article '
        '(propagation shader, directFaceSubtendedSolidAngle): 0.4006696846.',
        0.4006696846,
    ),
    'errata.dx11.side_solid_angle': (
        '\\Delta\\omega_{\\mathrm{side}}^{\\mathrm{printed}} = 0.4234413544',
        'side-face solid angle as printed in the DirectX 11 LPV implementation article '
        '(propagation shader, sideFaceSubtendedSolidAngle): 0.4234413544.',
        0.4234413544,
    ),
    'errata.dx11.front_weight': (
        'w_{\\mathrm{front}}^{\\mathrm{printed}} = \\frac{2003348423}{31415926000}',
        "front-face weight Δω_front/(4π) (Crytek's formula) as printed in the DirectX 11 LPV "
        'implementation article (propagation shader, directFaceSubtendedSolidAngle): '
        '0.4006696846f / Pi / 2.',
        0.06376856193893504,
    ),
    'errata.dx11.side_weight': (
        'w_{\\mathrm{side}}^{\\mathrm{printed}} = \\frac{529301693}{11780972250}',
        "side-face weight Δω_side/(4π) (Crytek's formula) as printed in the DirectX 11 LPV "
        'implementation article (propagation shader, sideFaceSubtendedSolidAngle): 0.4234413544f '
        '/ Pi / 3.',
        0.044928523874589385,
    ),
    'errata.dx11.side_eval_small': (
        'e_{\\mathrm{side},x}^{\\mathrm{printed}} = 0.4472135',
        'side evaluation direction, small component 1/√5 as printed in the DirectX 11 LPV '
        'implementation article (getEvalSideDirection, smallComponent): 0.4472135.',
        0.4472135,
    ),
    'errata.dx11.side_eval_big': (
        'e_{\\mathrm{side},y}^{\\mathrm{printed}} = 0.894427',
        'side evaluation direction, big component 2/√5 as printed in the DirectX 11 LPV '
        'implementation article (getEvalSideDirection, bigComponent): 0.894427.',
        0.894427,
    ),
    'errata.dx11.surfel_weight': (
        'w_{\\mathrm{surfel}}^{\\mathrm{printed}} = 0.015',
        'injection surfel weight as printed in the DirectX 11 LPV implementation article '
        '(injection pixel shader, surfelWeight): 0.015.',
        0.015,
    ),
    'errata.dx11.l1_accuracy': (
        '\\left(E_{L1} / E\\right)^{\\mathrm{printed}} = 0.75',
        'share of a clamped cosine kept by 4 SH coefficients as printed in the DirectX 11 LPV '
        'implementation article (Pros and cons, first con): about 75%.',
        0.75,
    ),
    'errata.dx12.y00': (
        'Y_{0}^{0}^{\\mathrm{printed}} = \\frac{1}{2 \\sqrt{\\pi}}',
        'Y(0, 0) as printed in the DirectX 12 LPV write-up (Spherical Harmonics, first two '
        'bands): √(1/(4π)).',
        0.28209479177387814,
    ),
    'errata.dx12.y1': (
        'c_{1}^{\\mathrm{printed}} = \\frac{\\sqrt{3}}{2 \\sqrt{\\pi}}',
        'coefficient of −y (the band-1 function Y(1, −1)) as printed in the DirectX 12 LPV '
        'write-up (Spherical Harmonics, first two bands): √(3/(4π)).',
        0.4886025119029199,
    ),
}
