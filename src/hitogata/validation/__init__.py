"""hitogata beside measured people: the validation set, the model's answers, the comparison.

`load_dataset` reads the published measurements (`data/validation/`),
`answer_dataset` runs the model on every row, `compare` and `summary` put the
two side by side; `hitogata.validation.identify` fits the tissue constants to
a chosen subset of the rows.
"""

from hitogata.validation.answers import SURFACES, Answer, RowAnswers, answer_dataset
from hitogata.validation.dataset import KINDS, Dataset, Row, Source, load_dataset, shipped_dataset_path
from hitogata.validation.table import Comparison, Share, compare, headline, summary

__all__ = ["Answer", "Comparison", "Dataset", "KINDS", "Row", "RowAnswers", "SURFACES", "Share", "Source",
           "answer_dataset", "compare", "headline", "load_dataset", "shipped_dataset_path", "summary"]
