#!/usr/bin/perl
# Used by tests/test_docs.sh for its `printed by: build/bench/NAME` marks.
# Lines of the block (ARGV[1]) that no format of the C source (ARGV[0])
# prints: adjacent string literals joined, each line of a literal a pattern
# in which %d and %f conversions match numbers and %s anything; or a line
# whose every piece between numbers and runs of spaces is a string literal
# of the source (a header printed with %s).
open my $s, '<', $ARGV[0] or die "$ARGV[0]: $!\n";
my $src = do { local $/; <$s> };
$src =~ s/"\s*\n\s*"//g;
my @pat;
sub conv {
	my ($c) = @_;
	return '\s*.*?' if $c =~ /[sc]$/;
	return '\s*[-+]?[0-9]+' if $c =~ /[diouxX]$/;
	return '\s*(?:[-+]?[0-9]*\.?[0-9]+(?:e[-+]?[0-9]+)?|nan|inf)';
}
while ($src =~ /"((?:[^"\\\n]|\\.)*)"/g) {
	for my $f (split /\\n/, $1) {
		$f =~ s/\\"/"/g; $f =~ s/\\t/\t/g; $f =~ s/%%/\x01/g;
		$f =~ s/^\s+|\s+$//g;
		# a pattern needs words or a number, not only %s
		(my $rest = $f) =~ s/%[-+ #0-9.*]*s//g;
		next unless $rest =~ /[A-Za-z]{2}|%[-+ #0-9.*]*(?:l|ll|z|h)?[diouxXfeEg]/;
		my $re = join '', map { /^%/ ? conv($_) : quotemeta($_) }
			split /(%[-+ #0-9.*]*(?:l|ll|z|h)?[diouxXfeEgGsc])/, $f;
		$re =~ s/\\\x01/%/g; $re =~ s/\x01/%/g;
		push @pat, qr/^$re$/;
	}
}
open my $b, '<', $ARGV[1] or die "$ARGV[1]: $!\n";
while (my $l = <$b>) {
	chomp $l; $l =~ s/^\s+|\s+$//g;
	next if $l eq '';
	next if grep { $l =~ $_ } @pat;
	# else a line of %s parts (a table's header): each piece between
	# numbers and runs of spaces is text the source holds
	my @pieces = grep { /[A-Za-z]{2}/ }
		split /\s{2,}|(?<![A-Za-z0-9_])[-+]?[0-9][0-9,.]*(?![A-Za-z0-9_])/, $l;
	print "$l\n" if !@pieces || grep { index($src, "\"$_\"") < 0 } @pieces;
}
