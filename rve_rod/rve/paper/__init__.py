"""The paper group's own RVE output and our cell run along it (issue 27).

`data` reads their biaxial rays, picture-frame shear and fitted surfaces (shipped in
`rve_rod/data/weeger_group_rve`) and finds their converged states; `comparison` runs our cell
along the same deformations and measures the agreement and the diagnosis's quantities
(docs/validation.md, "The paper group's RVE").
"""
