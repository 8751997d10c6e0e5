"""hitogata: a physically based, posable human body model for apparel design."""
