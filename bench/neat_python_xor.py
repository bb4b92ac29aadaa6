"""neat-python's XOR, one run, for bench_neat's row beside evo's XOR.

usage: python neat_python_xor.py CONFIG SEED

The run is neat-python's XOR example: fitness 4 minus the squared errors
on the four cases, stopping when a genome reaches the config's threshold
(3.9) or after 300 generations. It prints one line:

    evaluations N solved S generations G

N counts every genome evaluated (the population of each generation run),
S is 1 when the run reached the threshold.
"""
import sys

import neat

CASES = [((0.0, 0.0), 0.0), ((0.0, 1.0), 1.0), ((1.0, 0.0), 1.0),
         ((1.0, 1.0), 0.0)]
GENERATIONS = 300

evaluations = 0


def eval_genomes(genomes, config):
    global evaluations
    for _, genome in genomes:
        net = neat.nn.FeedForwardNetwork.create(genome, config)
        fitness = 4.0
        for inputs, want in CASES:
            out = net.activate(inputs)[0]
            fitness -= (out - want) ** 2
        genome.fitness = fitness
        evaluations += 1


def main():
    path, seed = sys.argv[1], int(sys.argv[2])
    config = neat.Config(neat.DefaultGenome, neat.DefaultReproduction,
                         neat.DefaultSpeciesSet, neat.DefaultStagnation,
                         path)
    pop = neat.Population(config, seed=seed)
    best = pop.run(eval_genomes, GENERATIONS)
    solved = best is not None and best.fitness >= config.fitness_threshold
    print(f"evaluations {evaluations} solved {int(solved)} "
          f"generations {pop.generation}")


if __name__ == "__main__":
    main()
