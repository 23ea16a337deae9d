"""The papers' experiments as data: scenario catalogues and their claims."""

from . import yang2018, yao2022

PAPERS = {"yang2018": yang2018, "yao2022": yao2022}
