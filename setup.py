"""Which packages the distribution holds: every folder under explorer/ and derivations/
found by setuptools (none listed by hand, so a new one such as explorer.ui.overlays
cannot be left out; namespace packages too, so that a data folder such as
explorer/site/assets is a package setuptools knows rather than one it warns about), plus
the resource folders that live at the top of the repository and ship inside the package
(explorer/resources.py finds them there when installed). Everything else is declared in
pyproject.toml."""

from setuptools import find_namespace_packages, setup

RESOURCE_PACKAGES = {
    "explorer.shaders": "shaders",
    "explorer.shaders.generated": "shaders/generated",
    "explorer.lessons_data": "lessons",
}
"""Package name -> the checkout folder it is built from (edited as files, hot reloaded and
read by the tests where they are)."""

setup(
    packages=find_namespace_packages(include=["explorer", "explorer.*", "derivations",
                                              "derivations.*"],
                                     exclude=["*.__pycache__"]) + list(RESOURCE_PACKAGES),
    package_dir=RESOURCE_PACKAGES,
)
